"""``belvedere run`` (rosrun) and ``belvedere rospack``: executables from belvedere's node
registry and from the user's packages, ROS's command-line arguments, and rospack's answers
(against Debian's rospack where it is installed)."""

from __future__ import annotations

import os
import re
import shutil
import signal
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from belvedere.cli import main
from belvedere.mappings import split_ros_args
from belvedere.nodes import MODULES
from belvedere.packages import BUILTIN_PACKAGES
from tests.conftest import EXAMPLES

BELVEDERE = [sys.executable, "-m", "belvedere"]


def _package(root: Path, name: str, deps: str = "") -> Path:
    pkg = root / name
    (pkg / "scripts").mkdir(parents=True)
    (pkg / "package.xml").write_text(
        f'<package format="2"><name>{name}</name><version>0.0.1</version>'
        f"<description>d</description><maintainer email='a@b.c'>a</maintainer>"
        f"<license>BSD</license><buildtool_depend>catkin</buildtool_depend>{deps}</package>"
    )
    return pkg


def test_ros_arguments_are_split_as_rosrun_does() -> None:
    plain, remaps, params, name, ns = split_ros_args(
        ["-d", "x.rviz", "chatter:=/talk", "_rate:=10", "_gain:=0.5", "_label:=hi", "_on:=true",
         "__name:=mine", "__ns:=/robot", "__log:=/tmp/x"]
    )  # fmt: skip
    assert plain == ["-d", "x.rviz"]
    assert remaps == {"chatter": "/talk"}
    assert params == {"rate": 10, "gain": 0.5, "label": "hi", "on": True}
    assert (name, ns) == ("mine", "/robot")


def test_a_users_script_runs_as_its_node(tmp_path: Path) -> None:
    pkg = _package(tmp_path, "learner")
    script = pkg / "scripts" / "hello.py"
    script.write_text("import sys\nprint('argv', sys.argv[1:], flush=True)\n")
    done = subprocess.run(
        [*BELVEDERE, "run", "--package-path", str(tmp_path), "--headless", "learner", "hello.py",
         "one", "chatter:=/talk", "__ns:=/r", "_k:=2"],
        capture_output=True, text=True, timeout=60, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    # as rosrun passes them: verbatim (rospy reads its remaps, _params and __ns itself)
    assert "argv ['one', 'chatter:=/talk', '__ns:=/r', '_k:=2']" in done.stdout
    assert "required node" not in done.stderr  # the run ends with its script, as rosrun's


@pytest.mark.parametrize(
    ("options", "named"),
    [
        (["--echo", "/chatter"], "--echo"),
        (["--pub", "/chatter std_msgs/String {data: hi}", "--duration", "1"], "--pub, --duration"),
        (["--rtf", "max"], "--rtf"),
    ],
)
def test_run_options_beside_a_running_graph_are_refused_not_ignored(
    peer: Any, tmp_path: Path, options: list[str], named: str
) -> None:
    """A script joining a running graph keeps that graph's time and runs until it ends: the
    options that shape a run of its own are refused, naming them, and the script never
    starts."""
    pkg = _package(tmp_path, "learner")
    script = pkg / "scripts" / "hello.py"
    script.write_text(f"open({str(tmp_path / 'ran')!r}, 'w').close()\n")
    done = subprocess.run(
        [*BELVEDERE, "run", "--package-path", str(tmp_path), *options, "learner", "hello.py"],
        capture_output=True, text=True, timeout=60, check=False,
    )  # fmt: skip
    assert done.returncode == 1
    assert done.stderr.startswith(f"error: {named}: a script run beside a running graph"), (
        done.stderr
    )
    assert not (tmp_path / "ran").exists()


def test_a_script_by_its_path(tmp_path: Path) -> None:
    script = tmp_path / "alone.py"
    script.write_text("print('ran', flush=True)\n")
    done = subprocess.run(
        [*BELVEDERE, "run", "--headless", str(script), "__name:=solo"],
        capture_output=True, text=True, timeout=60, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout == "ran\n"


def test_echo_of_a_scripts_topic_waits_for_the_script_to_advertise_it() -> None:
    """A script's topics are known once its process advertises them: ``--echo`` of one
    prints its messages instead of refusing the run before the script starts."""
    run = subprocess.Popen(
        [*BELVEDERE, "run", "--package-path", str(EXAMPLES), "--headless",
         "--echo", "/person_info", "learning_topic", "person_publisher.py"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    assert run.stdout is not None
    try:
        lines = iter(run.stdout.readline, "")
        assert next(line for line in lines if line.startswith("name:")) == 'name: "Tom"\n'
        assert next(lines) == "age: 18\n"
        assert next(lines) == "sex: 1\n"
    finally:
        run.send_signal(signal.SIGINT)  # Ctrl-C
        _, err = run.communicate(timeout=60)
    assert "Traceback" not in err, err


def test_echo_of_a_topic_no_script_advertises_ends_with_the_duration() -> None:
    done = subprocess.run(
        [*BELVEDERE, "run", "--headless", "--duration", "0.5", "--echo", "/nobody",
         str(EXAMPLES / "learning_topic/scripts/person_subscriber.py")],
        capture_output=True, text=True, timeout=60, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout == ""
    assert "--echo /nobody: no node of this run published it\n" in done.stderr


def test_a_registry_node_runs_in_process(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(
        ["run", "--rtf", "max", "--duration", "0.2", "--echo", "/tf_static", "--headless",
         "tf2_ros", "static_transform_publisher", "1", "2", "3", "0", "0", "0", "map", "odom",
         "__name:=stp"]
    )  # fmt: skip
    assert code == 0
    out = capsys.readouterr().out
    assert 'frame_id: "map"' in out
    assert 'child_frame_id: "odom"' in out
    assert "x: 1.0" in out


def test_a_nodes_log_prints_as_ros_prints_it(capsys: pytest.CaptureFixture[str]) -> None:
    """map_server logs as it loads (node.logger.info): on stdout, in ROS's format, with the
    simulated time after the wall clock's; -q hides it (rosrun says nothing itself)."""
    yaml = str(EXAMPLES / "mbot_navigation/maps/cloister_gmapping.yaml")
    argv = ["run", "--rtf", "max", "--duration", "0.1", "--headless"]
    argv += ["map_server", "map_server", yaml]
    assert main(argv) == 0
    out, err = capsys.readouterr()
    assert re.fullmatch(
        r'\[INFO\] \[\d+\.\d{6}, 0\.000000\]: Loading map from image "[^"]+'
        r'cloister_gmapping\.pgm"\n'
        r"\[INFO\] \[\d+\.\d{6}, 0\.000000\]: Read a 400 X 400 map @ 0\.050 m/cell\n",
        out,
    )
    assert "process[" not in err
    assert main(["run", "-q", *argv[1:]]) == 0  # belvedere's options come first
    assert capsys.readouterr().out == ""


def test_xacro_runs_the_xacro_verb(capsys: pytest.CaptureFixture[str]) -> None:
    model = EXAMPLES / "mbot_description/urdf/urdf/mbot_base.urdf"
    assert main(["run", "xacro", "xacro", str(model)]) == 0
    assert '<robot name="mbot">' in capsys.readouterr().out


def test_ros_tools_run_as_their_verbs(peer: Any, capsys: pytest.CaptureFixture[str]) -> None:
    """``rosrun rostopic rostopic list`` and the like: the tools ROS installs in their
    packages are belvedere's verbs, the same output."""
    for package, tool, verb, words in [
        ("rostopic", "rostopic", "topic", ["list"]),
        ("rosparam", "rosparam", "param", ["get", "/robot/speed"]),
        ("rosnode", "rosnode", "node", ["list"]),
        ("rosservice", "rosservice", "service", ["list"]),
        ("rosmsg", "rosmsg", "msg", ["md5", "std_msgs/String"]),
        ("rosmsg", "rossrv", "srv", ["show", "std_srvs/Trigger"]),
    ]:
        assert main([verb, *words]) == 0
        direct = capsys.readouterr().out
        assert main(["run", package, tool, *words]) == 0
        assert capsys.readouterr().out == direct, (package, tool)
        assert direct


def test_what_run_cannot_find(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    _package(tmp_path, "learner")
    assert main(["run", "--package-path", str(tmp_path), "learner", "nope.py"]) == 1
    assert "package 'learner' has no executable 'nope.py'" in capsys.readouterr().err
    assert main(["run", "robot_state_publisher", "rsp"]) == 1
    err = capsys.readouterr().err
    assert "belvedere has for robot_state_publisher: robot_state_publisher, state_publisher" in err
    assert main(["run", "--package-path", str(tmp_path), "learner"]) == 1
    assert "which executable?" in capsys.readouterr().err


def test_rospack_find_list_and_dependencies(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    _package(tmp_path, "base_pkg", "<exec_depend>a_system_lib</exec_depend>")
    _package(tmp_path, "mid", "<depend>base_pkg</depend><test_depend>nosetests</test_depend>")
    _package(tmp_path, "top", "<exec_depend>mid</exec_depend><build_depend>base_pkg</build_depend>")
    path = ["--package-path", str(tmp_path)]
    assert main(["rospack", "find", "top", *path]) == 0
    assert capsys.readouterr().out == f"{tmp_path / 'top'}\n"
    assert main(["rospack", "list-names", *path]) == 0
    names = capsys.readouterr().out.splitlines()
    assert names == sorted(names)
    assert {"base_pkg", "mid", "top"} <= set(names)
    assert main(["rospack", "depends1", "top", *path]) == 0
    assert capsys.readouterr().out == "mid\n"  # build-only and system dependencies left out
    assert main(["rospack", "depends", "top", *path]) == 0
    assert capsys.readouterr().out == "base_pkg\nmid\n"
    assert main(["rospack", "find", "nowhere", *path]) == 1
    assert "package 'nowhere' not found" in capsys.readouterr().err


def test_rospack_finds_the_packages_belvedere_provides_after_the_path(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """As ROS's rospack finds every installed package: belvedere's own (turtlesim, amcl …)
    after the package path, so a user's copy of one wins."""
    path = ["--package-path", str(tmp_path)]
    assert main(["rospack", "find", "turtlesim", *path]) == 0
    assert capsys.readouterr().out == f"{BUILTIN_PACKAGES / 'turtlesim'}\n"
    _package(tmp_path, "amcl")
    assert main(["rospack", "find", "amcl", *path]) == 0
    assert capsys.readouterr().out == f"{tmp_path / 'amcl'}\n"
    assert main(["rospack", "list", *path]) == 0
    listed = dict(line.split(" ") for line in capsys.readouterr().out.splitlines())
    assert listed["amcl"] == str(tmp_path / "amcl")
    assert listed["gazebo_ros"] == str(BUILTIN_PACKAGES / "gazebo_ros")
    assert set(MODULES) <= set(listed)  # every package with executables belvedere has
    assert main(["rospack", "depends1", "gazebo_ros", *path]) == 0
    assert capsys.readouterr().out == ""


@pytest.mark.skipif(shutil.which("rospack", path="/usr/bin") is None, reason="no rospack")
@pytest.mark.parametrize("command", ["depends", "depends1"])
@pytest.mark.parametrize("package", ["mbot_gazebo", "mbot_description", "marm_description"])
def test_rospack_answers_as_debians(
    command: str, package: str, capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """Over the examples and Debian's ROS packages (/usr/share): the same lines in the same
    order as the real rospack."""
    env = {**os.environ, "PATH": "/usr/bin:" + os.environ["PATH"], "ROS_HOME": str(tmp_path)}
    # belvedere's own packages last, where belvedere finds them (mbot_gazebo needs gazebo_ros)
    env["ROS_PACKAGE_PATH"] = f"{EXAMPLES}:/usr/share:{BUILTIN_PACKAGES}"
    real = subprocess.run(
        ["rospack", command, package], capture_output=True, text=True, env=env, check=True
    ).stdout
    assert main(["rospack", command, package, "--package-path", str(EXAMPLES),
                 "--package-path", "/usr/share"]) == 0  # fmt: skip
    assert capsys.readouterr().out == real


def test_a_python_2_script_runs(tmp_path: Path) -> None:
    pkg = _package(tmp_path, "course")
    (pkg / "scripts" / "old.py").write_bytes(b"#!/usr/bin/env python\r\nprint 'old', 2\r\n")
    done = subprocess.run(
        [*BELVEDERE, "run", "--package-path", str(tmp_path), "--headless", "course", "old.py"],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
        env={**os.environ, "XDG_CACHE_HOME": str(tmp_path / "cache")},
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout == "old 2\n"
    assert "old.py: a Python 2 script: running its Python 3 form" in done.stderr
