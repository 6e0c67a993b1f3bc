"""Every example launch file runs: it starts, its topics appear with the expected types and
rates, and it shuts down cleanly."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest

from belvedere.cli import main
from belvedere.graph import Graph
from belvedere.launch import LaunchError, load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.msgs import types
from belvedere.packages import PackageIndex
from tests.conftest import EXAMPLES
from tests.waiting import DEADLINE

DESCRIPTION = EXAMPLES / "mbot_description/launch"
GAZEBO = EXAMPLES / "mbot_gazebo/launch"

STATE = {"/joint_states": ("sensor_msgs/JointState", 10.0), "/tf": ("tf2_msgs/TFMessage", None)}
ARBOTIX = {  # joint_states from both the driver (placeholder wheels) and joint_state_publisher
    "/joint_states": ("sensor_msgs/JointState", 20.0),
    "/tf": ("tf2_msgs/TFMessage", None),
    "/odom": ("nav_msgs/Odometry", 10.0),
}
PHYSICS = {
    "/odom": ("nav_msgs/Odometry", 100.0),
    "/clock": ("rosgraph_msgs/Clock", 100.0),
    "/gazebo/model_states": ("gazebo_msgs/ModelStates", None),
}

CASES: list[tuple[Path, dict[str, tuple[str, float | None]], float]] = [
    (DESCRIPTION / "display_mbot_base_urdf.launch", STATE, 2.0),
    (DESCRIPTION / "display_mbot_gazebo_xacro.launch", STATE, 2.0),
    (DESCRIPTION / "display_mbot_with_camera_xacro.launch", STATE, 2.0),
    (DESCRIPTION / "display_mbot_with_kinect_xacro.launch", STATE, 2.0),
    (DESCRIPTION / "display_mbot_with_laser_xacro.launch", STATE, 2.0),
    (DESCRIPTION / "arbotix_mbot_with_camera_xacro.launch", ARBOTIX, 2.0),
    (DESCRIPTION / "arbotix_mbot_with_kinect_xacro.launch", ARBOTIX, 2.0),
    (DESCRIPTION / "arbotix_mbot_with_laser_xacro.launch", ARBOTIX, 2.0),
    (GAZEBO / "view_mbot_gazebo_empty_world.launch", PHYSICS, 2.0),
    (GAZEBO / "view_mbot_gazebo_play_ground.launch", PHYSICS, 2.0),
    (
        GAZEBO / "view_mbot_with_laser_gazebo.launch",
        {**PHYSICS, "/scan": ("sensor_msgs/LaserScan", 5.5)},
        2.0,
    ),
    (
        GAZEBO / "view_mbot_with_camera_gazebo.launch",
        {"/camera/image_raw": ("sensor_msgs/Image", 30.0)},
        0.2,
    ),
    (
        GAZEBO / "view_mbot_with_kinect_gazebo.launch",
        {"/kinect/depth/image_raw": ("sensor_msgs/Image", 10.0)},
        0.5,
    ),
    (
        EXAMPLES / "marm_description/launch/marm_gazebo_control.launch",
        {
            "/marm/joint_states": ("sensor_msgs/JointState", 50.0),
            "/tf": ("tf2_msgs/TFMessage", None),
        },
        2.0,
    ),
    (
        EXAMPLES / "rbx1_bringup/launch/fake_turtlebot.launch",
        {"/odom": ("nav_msgs/Odometry", 10.0)},
        2.0,
    ),
]


@pytest.mark.parametrize(("path", "expected", "seconds"), CASES, ids=[c[0].name for c in CASES])
def test_example_launch_runs(
    path: Path, expected: dict[str, tuple[str, float | None]], seconds: float
) -> None:
    packages = PackageIndex([EXAMPLES])
    config = load_launch(path, packages=packages)
    graph = Graph()
    runtime = LaunchRuntime(config, graph, packages, headless=True)
    runtime.start()
    assert not runtime.missing
    probe = graph.create_node("probe")
    counts: dict[str, list[Any]] = {topic: [] for topic in expected}
    for topic, (msg_type, _) in expected.items():
        probe.subscribe(topic, msg_type, counts[topic].append, queue_size=0)
    graph.run(duration=seconds)
    for topic, (msg_type, rate) in expected.items():
        assert graph.topics[topic].type == types().resolve(msg_type), topic
        assert counts[topic], f"nothing on {topic}"
        if rate is not None:
            assert len(counts[topic]) == pytest.approx(rate * seconds, rel=0.1, abs=1), topic
    runtime.close()
    graph.shutdown()


def test_arbotix_launch_drives_the_robot() -> None:
    packages = PackageIndex([EXAMPLES])
    config = load_launch(DESCRIPTION / "arbotix_mbot_with_laser_xacro.launch", packages=packages)
    graph = Graph()
    LaunchRuntime(config, graph, packages, headless=True).start()
    probe = graph.create_node("probe")
    odom: list[Any] = []
    probe.subscribe("/odom", "nav_msgs/Odometry", odom.append)
    probe.publisher("/cmd_vel", "geometry_msgs/Twist", latch=True).publish_data(
        {"linear": {"x": 0.2}}
    )
    graph.run(duration=1.0)
    assert odom[-1].pose.pose.position.x == pytest.approx(0.2)
    assert odom[-1].child_frame_id == "base_footprint"


def test_marm_controllers_are_spawned() -> None:
    packages = PackageIndex([EXAMPLES])
    config = load_launch(
        EXAMPLES / "marm_description/launch/marm_gazebo_control.launch", packages=packages
    )
    graph = Graph()
    runtime = LaunchRuntime(config, graph, packages, headless=True)
    runtime.start()
    client = graph.create_node("client")
    listed = client.call_service(
        "/marm/controller_manager/list_controllers", "controller_manager_msgs/ListControllers"
    )
    assert {c.name for c in listed.controller if c.state == "running"} == {
        "joint_state_controller",
        "arm_controller",
        "gripper_controller",
    }


def test_missing_node_types_are_one_line_and_the_rest_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], endpoint: str
) -> None:
    script = tmp_path / "pkg" / "scripts"
    script.mkdir(parents=True)
    (tmp_path / "pkg" / "package.xml").write_text("<package><name>mypkg</name></package>")
    (script / "talker.py").write_text("import rospy\n")
    launch = tmp_path / "pkg" / "all.launch"
    launch.write_text(
        """<launch>
          <node pkg="rosbridge_server" type="rosbridge_tcp" name="rosbridge"/>
          <node pkg="mypkg" type="talker.py" name="talker"/>
          <node pkg="tf" type="static_transform_publisher" name="stp"
                args="1 0 0 0 0 0 map odom 100"/>
        </launch>"""
    )
    args = ["launch", str(launch), "--headless", "--rtf", "max", "--duration", "0.5"]
    assert main([*args, "--echo", "/tf_static"]) == 0
    out, err = capsys.readouterr()
    assert "not started (belvedere has no such node yet): rosbridge_server/rosbridge_tcp" in err
    assert 'child_frame_id: "odom"' in out


def test_cli_listing_options(capsys: pytest.CaptureFixture[str], endpoint: str) -> None:
    base = ["launch", "--package-path", str(EXAMPLES), "mbot_gazebo"]
    launch = "view_mbot_gazebo_empty_world.launch"
    assert main([*base, launch, "--nodes"]) == 0
    assert capsys.readouterr().out.split() == [
        "/gazebo",
        "/gazebo_gui",
        "/joint_state_publisher",
        "/robot_state_publisher",
        "/urdf_spawner",
    ]
    assert main([*base, launch, "gui:=false", "--nodes"]) == 0
    assert "/gazebo_gui" not in capsys.readouterr().out
    assert main([*base, launch, "--files"]) == 0
    files = capsys.readouterr().out.splitlines()
    assert files[0].endswith("view_mbot_gazebo_empty_world.launch")
    assert files[1].endswith("gazebo_ros/launch/empty_world.launch")
    assert main([*base, launch, "--args", "urdf_spawner"]) == 0
    assert "gazebo_ros/spawn_model -urdf -model mrobot" in capsys.readouterr().out
    assert main([*base, launch, "--dump-params"]) == 0
    assert "use_sim_time: true" in capsys.readouterr().out
    assert main([*base, launch, "nope:=1", "--nodes"]) == 1
    assert "unused args ['nope']" in capsys.readouterr().err


def test_depthimage_to_laserscan_on_the_kinect(tmp_path: Path) -> None:
    launch = tmp_path / "kinect_scan.launch"
    launch.write_text(
        f"""<launch>
          <include file="{GAZEBO / "view_mbot_with_kinect_gazebo.launch"}">
            <arg name="gui" value="false"/>
          </include>
          <node pkg="depthimage_to_laserscan" type="depthimage_to_laserscan" name="d2l">
            <remap from="image" to="/kinect/depth/image_raw"/>
            <remap from="camera_info" to="/kinect/depth/camera_info"/>
            <param name="output_frame_id" value="kinect_link"/>
          </node>
        </launch>"""
    )
    packages = PackageIndex([EXAMPLES])
    graph = Graph()
    LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True).start()
    scans: list[Any] = []
    graph.create_node("probe").subscribe("/scan", "sensor_msgs/LaserScan", scans.append)
    graph.run(duration=0.5)
    assert scans
    scan = scans[-1]
    assert scan.header.frame_id == "kinect_link"
    assert len(scan.ranges) == 640
    assert scan.angle_max == pytest.approx(-scan.angle_min, abs=0.01)  # 60 degree fov
    assert scan.angle_max == pytest.approx(0.5236, abs=0.01)


def test_required_script_ends_the_launch_and_params_are_dumped(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], endpoint: str
) -> None:
    pkg = tmp_path / "pkg"
    (pkg / "scripts").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>mypkg</name></package>")
    (pkg / "scripts" / "quick.py").write_text("import sys\nsys.exit(0)\n")
    dump = tmp_path / "params.yaml"
    launch = pkg / "quick.launch"
    launch.write_text(
        f"""<launch>
          <param name="speed" value="0.3"/>
          <rosparam command="dump" file="{dump}"/>
          <node pkg="mypkg" type="quick.py" name="quick" required="true"/>
        </launch>"""
    )
    # paced at real time; the duration only bounds the run should the script never end it
    assert main(["launch", str(launch), "--headless", "--duration", str(DEADLINE)]) == 0
    err = capsys.readouterr().err
    assert "=" * 80 + "REQUIRED process [quick-2] has died!\nprocess has finished cleanly\n" in err
    assert "speed: 0.3" in dump.read_text()


def test_launch_prints_roslaunchs_summary_and_the_processes_it_starts(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], endpoint: str
) -> None:
    pkg = tmp_path / "pkg"
    (pkg / "scripts").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>mypkg</name></package>")
    (pkg / "scripts" / "quick.py").write_text("import sys\nsys.exit(0)\n")
    launch = pkg / "small.launch"
    launch.write_text(
        """<launch>
          <param name="speed" value="0.3"/>
          <group ns="r1">
            <node pkg="tf2_ros" type="static_transform_publisher" name="camera_tf"
                  args="0 0 0.2 0 0 0 base_link camera"/>
          </group>
          <node pkg="mypkg" type="quick.py" name="quick" required="true"/>
        </launch>"""
    )
    argv = ["launch", str(launch), "--headless", "--duration", str(DEADLINE)]
    assert main(argv) == 0
    out, err = capsys.readouterr()
    summary = (
        "\nSUMMARY\n========\n\nPARAMETERS\n * /speed: 0.3\n\nNODES\n  /\n"
        "    quick (mypkg/quick.py)\n  /r1/\n"
        "    camera_tf (tf2_ros/static_transform_publisher)\n\n"
    )
    assert err.startswith(summary)
    lines = err[len(summary) :].splitlines()
    assert lines[0].startswith("graph: domain ")
    # roslaunch's own roscore's rosout is process 1
    assert lines[1] == "process[r1/camera_tf-2]: started in this process"
    assert re.fullmatch(r"process\[quick-3\]: started with pid \[\d+\]", lines[2])
    assert out == ""
    assert main([*argv, "-q"]) == 0
    assert "SUMMARY" not in capsys.readouterr().err


def test_a_dump_that_does_not_fit_keeps_the_old_file(
    tmp_path: Path, full_disk: Path, capsys: pytest.CaptureFixture[str], endpoint: str
) -> None:
    dump = full_disk / "params.yaml"
    dump.write_text("previous: 1\n")
    launch = tmp_path / "dump.launch"
    launch.write_text(
        f"""<launch>
          <param name="big" value="{"x" * 70_000}"/>
          <rosparam command="dump" file="{dump}"/>
        </launch>"""
    )
    assert main(["launch", str(launch), "--headless", "--duration", "0.1"]) == 0
    err = capsys.readouterr().err
    assert (
        f"warning: rosparam dump: cannot write {dump}: No space left on device; "
        f"{dump} is unchanged\n" in err
    )
    assert dump.read_text() == "previous: 1\n"
    assert sorted(p.name for p in full_disk.iterdir()) == ["params.yaml"]


def test_spawning_a_model_the_world_already_has_names_both_places(tmp_path: Path) -> None:
    # A world saved by Gazebo while the robot was in it keeps the robot; launching it with
    # the spawner again is refused, as gazebo_ros refuses it.
    world = tmp_path / "room.world"
    world.write_text(
        "<sdf version='1.7'><world name='default'>\n"
        "  <include><uri>model://ground_plane</uri></include>\n"
        "  <model name='mrobot'>\n"
        "    <link name='base_footprint'/>\n"
        "  </model>\n"
        "</world></sdf>\n"
    )
    launch = tmp_path / "room.launch"
    launch.write_text(
        f"""<launch>
  <include file="$(find gazebo_ros)/launch/empty_world.launch">
    <arg name="world_name" value="{world}"/>
    <arg name="gui" value="false"/>
  </include>
  <param name="robot_description" textfile="$(find mbot_description)/urdf/urdf/mbot_base.urdf"/>
  <node name="urdf_spawner" pkg="gazebo_ros" type="spawn_model"
        args="-urdf -model mrobot -param robot_description"/>
</launch>
"""
    )
    packages = PackageIndex([EXAMPLES])
    graph = Graph()
    runtime = LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True)
    with pytest.raises(LaunchError) as info:
        runtime.start()
    text = info.value.describe()
    assert text.startswith(f"{launch}:7:")
    assert "SpawnModel: Failure - model name mrobot already exist." in text
    assert f"the world already has a model named 'mrobot', at {world}:3:3" in text
    runtime.close()
    graph.shutdown()


def test_two_spawners_of_one_name_name_both_places(tmp_path: Path) -> None:
    launch = tmp_path / "twice.launch"
    launch.write_text(
        """<launch>
  <include file="$(find gazebo_ros)/launch/empty_world.launch">
    <arg name="gui" value="false"/>
  </include>
  <param name="rd" textfile="$(find mbot_description)/urdf/urdf/mbot_base.urdf"/>
  <node name="first" pkg="gazebo_ros" type="spawn_model" args="-urdf -model r -param rd"/>
  <node name="second" pkg="gazebo_ros" type="spawn_model" args="-urdf -model r -param rd"/>
</launch>
"""
    )
    packages = PackageIndex([EXAMPLES])
    graph = Graph()
    runtime = LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True)
    with pytest.raises(LaunchError, match=rf"\(/first, at {launch}:6:\d+, spawned a model") as info:
        runtime.start()
    assert str(info.value.location).startswith(f"{launch}:7:")
    runtime.close()
    graph.shutdown()


BUILTIN = Path(__file__).parents[2] / "src" / "belvedere" / "share" / "packages"


@pytest.mark.parametrize(
    ("launch", "listed"),
    [
        (
            GAZEBO / "view_mbot_gazebo_empty_world.launch",
            [
                ("launch", GAZEBO / "view_mbot_gazebo_empty_world.launch"),
                ("launch", BUILTIN / "gazebo_ros/launch/empty_world.launch"),
                ("xacro", EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_gazebo.xacro"),
                ("xacro", EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_base_gazebo.xacro"),
                ("world", EXAMPLES / "mbot_gazebo/worlds/empty.world"),
            ],
        ),
        (
            EXAMPLES / "mbot_navigation/launch/nav_cloister_demo.launch",
            [
                ("launch", EXAMPLES / "mbot_navigation/launch/nav_cloister_demo.launch"),
                ("launch", EXAMPLES / "mbot_navigation/launch/move_base.launch"),
                *(
                    ("yaml", EXAMPLES / f"mbot_navigation/config/mbot/{name}_params.yaml")
                    for name in (
                        "costmap_common",
                        "local_costmap",
                        "global_costmap",
                        "base_local_planner",
                    )
                ),
                ("launch", EXAMPLES / "mbot_navigation/launch/amcl.launch"),
                ("map", EXAMPLES / "mbot_navigation/maps/cloister_gmapping.yaml"),
                ("image", EXAMPLES / "mbot_navigation/maps/cloister_gmapping.pgm"),
                ("rviz", EXAMPLES / "mbot_navigation/rviz/nav.rviz"),
            ],
        ),
        (
            DESCRIPTION / "display_mbot_base_urdf.launch",
            [
                ("launch", DESCRIPTION / "display_mbot_base_urdf.launch"),
                ("urdf", EXAMPLES / "mbot_description/urdf/urdf/mbot_base.urdf"),
                ("rviz", EXAMPLES / "mbot_description/config/mbot.rviz"),
            ],
        ),
    ],
    ids=lambda v: v.name if isinstance(v, Path) else "",
)
def test_files_lists_every_file_the_launch_reads_by_kind(
    launch: Path, listed: list[tuple[str, Path]], capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["-q", "launch", str(launch), "--files"]) == 0
    width = max(len(kind) for kind, _ in listed)
    assert capsys.readouterr().out == "".join(
        f"{kind:<{width}}  {path.resolve() if kind != 'launch' or path != launch else path}\n"
        for kind, path in listed
    )
