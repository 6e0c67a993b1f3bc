"""Did-you-mean hints for a misspelt package, executable, launch file or launch arg."""

from __future__ import annotations

from pathlib import Path

import pytest

from belvedere.cli import main
from belvedere.errors import did_you_mean
from belvedere.packages import BUILTIN_PACKAGES
from tests.conftest import EXAMPLES

GAZEBO = EXAMPLES / "mbot_gazebo" / "launch"
EMPTY = GAZEBO / "view_mbot_gazebo_empty_world.launch"
PATH_HINT = "add its parent directory with --package-path DIR, or set ROS_PACKAGE_PATH"


def test_did_you_mean() -> None:
    assert did_you_mean("guii", ["gui", "paused", "debug"]) == "did you mean 'gui'?"
    assert did_you_mean("zzz", ["gui", "paused"]) is None
    assert did_you_mean("base_link", ["base_footprint", "base_lnk", "arm"], most=2) == (
        "did you mean 'base_lnk' or 'base_footprint'?"  # the closest first
    )


def test_find_of_a_misspelt_package(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    robot = tmp_path / "robot.xacro"
    robot.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:include filename="$(find mbot_descripton)/urdf/xacro/gazebo/'
        'mbot_base_gazebo.xacro"/>\n'
        "</robot>\n"
    )
    expected = (
        f"{robot}:2:3: error: package 'mbot_descripton' not found; searched:\n"
        f"    {EXAMPLES}\n"
        f"  hint: did you mean 'mbot_description'? Otherwise {PATH_HINT}\n"
    )
    for verb in ("xacro", "check"):
        assert main(["--package-path", str(EXAMPLES), verb, str(robot)]) == 1
        assert capsys.readouterr().err == expected


def test_run_with_a_misspelt_package_or_executable(capsys: pytest.CaptureFixture[str]) -> None:
    path = ["--package-path", str(EXAMPLES)]
    assert main([*path, "run", "mbot_telop", "mbot_teleop.py"]) == 1
    assert capsys.readouterr().err.endswith(
        f"  hint: did you mean 'mbot_teleop'? Otherwise {PATH_HINT}\n"
    )
    assert main([*path, "run", "mbot_teleop", "mbot_telop.py"]) == 1
    assert capsys.readouterr().err == (
        "error: package 'mbot_teleop' has no executable 'mbot_telop.py'\n"
        "  hint: did you mean 'mbot_teleop.py'?\n"
    )
    # a package belvedere has in itself, with nothing of it on the package path
    assert main(["run", "map_server", "map_sever"]) == 1
    assert capsys.readouterr().err == (
        "error: package 'map_server' has no executable 'map_sever'\n"
        "  hint: did you mean 'map_server'?\n"
    )


def test_launch_of_a_misspelt_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = ["--package-path", str(EXAMPLES)]
    assert main([*path, "launch", "mbot_gazeb", EMPTY.name]) == 1
    assert capsys.readouterr().err.endswith(
        f"  hint: did you mean 'mbot_gazebo'? Otherwise {PATH_HINT}\n"
    )
    assert main([*path, "launch", "mbot_gazebo", "view_mbot_gazebo_empty_wrld.launch"]) == 1
    assert capsys.readouterr().err == (
        "error: no launch file 'view_mbot_gazebo_empty_wrld.launch' in package 'mbot_gazebo' "
        f"({EXAMPLES / 'mbot_gazebo'})\n"
        "  hint: did you mean 'view_mbot_gazebo_empty_world.launch'?\n"
    )
    assert main([*path, "launch", "mbot_gazebo", "nothing_like_it.launch"]) == 1
    assert capsys.readouterr().err.endswith(
        "  hint: the package's launch files: mbot_laser_nav_gazebo.launch, "
        "multi_mbot.launch, namespaced_mbot.launch, "
        "view_mbot_gazebo_empty_world.launch, view_mbot_gazebo_play_ground.launch, "
        "view_mbot_gazebo_room.launch, "
        "view_mbot_with_camera_gazebo.launch, view_mbot_with_kinect_gazebo.launch, "
        "view_mbot_with_laser_gazebo.launch\n"
    )
    missing = GAZEBO / "view_mbot_gazebo_empty_wrld.launch"
    assert main(["launch", str(missing)]) == 1
    assert capsys.readouterr().err == (
        f"error: launch file '{missing}' does not exist\n"
        "  hint: did you mean 'view_mbot_gazebo_empty_world.launch'?\n"
    )
    includer = tmp_path / "outer.launch"
    includer.write_text(f'<launch>\n  <include file="{missing}"/>\n</launch>\n')
    assert main(["launch", str(includer), "--nodes"]) == 1
    assert capsys.readouterr().err == (
        f"{includer}:2:3: error: launch file '{missing}' does not exist\n"
        "  hint: did you mean 'view_mbot_gazebo_empty_world.launch'?\n"
    )


EMPTY_WORLD_ARGS = (
    "command_arg1, command_arg2, command_arg3, debug, enable_ros_network, extra_gazebo_args, "
    "gui, gui_required, headless, output, paused, physics, pub_clock_frequency, recording, "
    "respawn_gazebo, script_type, server_required, use_clock_frequency, use_sim_time, verbose, "
    "world_name"
)


def test_an_unknown_launch_arg_names_the_declared_ones(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["-q", "launch", str(EMPTY), "guii:=false", "--nodes"]) == 1
    assert capsys.readouterr().err == (
        f"{EMPTY}:1:1: error: unused args ['guii'] given by the command line for {EMPTY}\n"
        "  hint: did you mean 'gui'?\n"
        "        args this file declares: debug, gui, headless, paused, use_sim_time, "
        "world_name\n"
        f"        {BUILTIN_PACKAGES / 'gazebo_ros/launch/empty_world.launch'} declares: "
        f"{EMPTY_WORLD_ARGS}\n"
    )
    assert main(["-q", "launch", str(EMPTY), "gui:=false", "--nodes"]) == 0


def test_an_unknown_arg_of_an_include(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    inner = tmp_path / "inner.launch"
    inner.write_text('<launch>\n  <arg name="rate" default="1"/>\n</launch>\n')
    outer = tmp_path / "outer.launch"
    outer.write_text(
        f'<launch>\n  <include file="{inner}">\n    <arg name="rtae" value="2"/>\n'
        "  </include>\n</launch>\n"
    )
    assert main(["launch", str(outer), "--nodes"]) == 1
    assert capsys.readouterr().err == (
        f"{outer}:2:3: error: unused args ['rtae'] given by the <include> at {outer}:2:3 for "
        f"{inner}\n"
        "  hint: did you mean 'rate'?\n"
        "        args this file declares: rate\n"
    )
