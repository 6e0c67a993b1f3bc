"""Nodes live and die as roslaunch's processes, with real processes: ``belvedere launch`` in a
process of its own, its scripts in theirs.

A node that fails dies alone, with roslaunch's line, and the launch runs on; a required one
ends the launch with roslaunch's banner; one with ``respawn`` is restarted; the launch's exit
status is roslaunch's, 0. The course's room, saved from Gazebo with the robot in it, runs with
that robot (it drives, it scans) while the spawner of a second one dies.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
import yaml

from belvedere.graph import Graph, ZenohTransport, graph_running
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.packages import PackageIndex
from tests.conftest import EXAMPLES, free_port
from tests.debian_ros import missing_debian_ros
from tests.waiting import DEADLINE, wait_until

BELVEDERE = [sys.executable, "-m", "belvedere"]
ROSLAUNCH = Path("/usr/bin/roslaunch")
PACKAGE_XML = "<package><name>life</name><version>0.0.0</version></package>\n"

EXIT_WITH = """#!/usr/bin/env python3
import sys
import rospy
rospy.init_node("exit_with")
words = rospy.myargv()
if len(words) > 2:
    open(words[2], "w").close()  # a mark that it ran
sys.exit(int(words[1]))
"""

COUNT = """#!/usr/bin/env python3
import os, sys
import rospy
rospy.init_node("count")
counter, *marks = rospy.myargv()[1:]
if all(os.path.exists(m) for m in marks):
    with open(counter, "a") as f:
        f.write("x")
sys.exit(1)
"""

BOSS = """#!/usr/bin/env python3
import os, sys, time
import rospy
rospy.init_node("boss")
counter = rospy.myargv()[1]
while not os.path.exists(counter) or len(open(counter).read()) < 2:
    time.sleep(0.05)
sys.exit(3)
"""

HOLD = """#!/usr/bin/env python3
import rospy
rospy.init_node("hold")
rospy.spin()
"""

SCRIPTS = {"exit_with.py": EXIT_WITH, "count.py": COUNT, "boss.py": BOSS, "hold.py": HOLD}

LIFE = """<launch>
  <node pkg="life" type="exit_with.py" name="clean" args="0 {work}/clean"/>
  <node pkg="life" type="exit_with.py" name="fails" args="1 {work}/fails" output="screen"/>
  <node pkg="life" type="count.py" name="again" args="{work}/counter {work}/clean {work}/fails"
        respawn="true" respawn_delay="1"/>
  <node pkg="life" type="hold.py" name="holder"/>
  <node pkg="life" type="boss.py" name="boss" args="{work}/counter" required="true"/>
</launch>
"""
"""Each kind of end: clean exit, exit 1, respawn (each run after the first two marks counts),
a process that stays, and a required one that exits 3 once ``again`` counted twice: by then
the first two have ended more than a respawn delay ago, so both sides have reported them."""


def life_package(root: Path) -> Path:
    """A package ``life`` with the scripts, and the launch file (returned)."""
    pkg = root / "life"
    (pkg / "scripts").mkdir(parents=True)
    (pkg / "package.xml").write_text(PACKAGE_XML)
    for name, text in SCRIPTS.items():
        path = pkg / "scripts" / name
        path.write_text(text)
        path.chmod(0o755)
    work = root / "work"
    work.mkdir()
    launch = pkg / "life.launch"
    launch.write_text(LIFE.format(work=work))
    return launch


def lifecycle_lines(text: str, log_root: Path) -> list[str]:
    """roslaunch's lifecycle lines of an output, the run's own parts masked: pids, the log
    directory (its run id), colours."""
    text = re.sub(r"\x1b\[[0-9;]*m", "", text)
    text = text.replace(str(log_root), "LOG")
    text = re.sub(r"LOG/[0-9a-f-]{36}", "LOG/RUN", text)
    text = re.sub(r"pid \[?\d+\]?", "pid PID", text)
    wanted = re.compile(
        r"^(=*REQUIRED process|process has|log file:|Initiating shutdown|\[[\w/-]+-\d+\] "
        r"(process has|restarting process))"
    )
    return [line for line in text.splitlines() if wanted.match(line)]


def belvedere_launch(launch: Path, env: dict[str, str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [*BELVEDERE, "launch", str(launch), "--headless", "--duration", str(4 * DEADLINE)],
        capture_output=True,
        text=True,
        env=env,
        timeout=5 * DEADLINE,
        check=False,
    )


def test_each_kind_of_node_ends_as_with_roslaunch(
    tmp_path: Path, endpoint: str, own_log_dir: Path
) -> None:
    launch = life_package(tmp_path)
    env = {**os.environ, "ROS_PACKAGE_PATH": str(tmp_path)}
    done = belvedere_launch(launch, env)
    assert done.returncode == 0, done.stderr  # roslaunch's, whatever ended it
    lines = lifecycle_lines(done.stderr, own_log_dir)
    script = tmp_path / "life" / "scripts"
    assert "[clean-2] process has finished cleanly" in lines
    assert lines[lines.index("[clean-2] process has finished cleanly") + 1] == (
        "log file: LOG/RUN/clean-2*.log"
    )
    assert (
        "[fails-3] process has died [pid PID, exit code 1, cmd "
        f"{script}/exit_with.py 1 {tmp_path}/work/fails __name:=fails "
        "__log:=LOG/RUN/fails-3.log]."
    ) in lines
    assert "[again-4] restarting process" in lines
    died = [line for line in lines if line.startswith("[again-4] process has died")]
    assert len(died) >= 2  # each run of it dies, and is reported
    banner = lines.index("=" * 80 + "REQUIRED process [boss-6] has died!")
    assert lines[banner + 1].startswith("process has died [pid PID, exit code 3, cmd ")
    assert lines[banner + 2 : banner + 4] == [
        "log file: LOG/RUN/boss-6*.log",
        "Initiating shutdown!",
    ]
    assert not any("holder" in line for line in lines)  # it ran until the end
    assert "[holder-5] killing on exit" in done.stderr
    # output="log": the script's stdout is in its log file, as roslaunch keeps it
    assert len(list(own_log_dir.glob("*/again-4-stdout.log"))) == 1


def _documents(text: str) -> dict[str, list[Any]]:
    """``--echo`` of several topics: each message by its topic."""
    by_topic: dict[str, list[Any]] = {}
    for doc in text.split("\n---\n"):
        if doc.strip():
            header, _, body = doc.strip().partition("\n")
            by_topic.setdefault(header.removeprefix("# "), []).append(yaml.safe_load(body))
    return by_topic


def test_the_room_saved_with_the_robot_runs_it_and_refuses_a_second(
    endpoint: str, own_log_dir: Path
) -> None:
    """The course's view_mbot_gazebo_room.launch: its room.world was saved from Gazebo with
    mrobot in it. Gazebo refuses the spawner's second mrobot; the spawner dies; the world runs
    on with the robot it holds, which drives on /cmd_vel (odometry moves) and scans."""
    argv = [*BELVEDERE, "launch", "--package-path", str(EXAMPLES), "mbot_gazebo"]
    argv += ["view_mbot_gazebo_room.launch", "gui:=false", "--headless", "--rtf", "max"]
    argv += ["--duration", "2", "--pub", "/cmd_vel geometry_msgs/Twist {linear: {x: 0.3}}"]
    argv += ["--echo", "/odom", "--echo", "/scan"]
    done = subprocess.run(argv, capture_output=True, text=True, timeout=5 * DEADLINE)
    assert done.returncode == 0, done.stderr
    launch = EXAMPLES / "mbot_gazebo" / "launch" / "view_mbot_gazebo_room.launch"
    world = EXAMPLES / "mbot_gazebo" / "worlds" / "room.world"
    line = (
        launch.read_text()
        .splitlines()
        .index(
            '    <node name="urdf_spawner" pkg="gazebo_ros"'
            ' type="spawn_model" respawn="false" output="screen"'
        )
        + 1
    )
    assert (
        f"{launch}:{line}:5: error: spawn_model -model mrobot: SpawnModel: Failure - model name "
        f"mrobot already exist. (the world already has a model named 'mrobot', at {world}:"
    ) in done.stderr
    lines = lifecycle_lines(done.stderr, own_log_dir)
    assert lines[:2] == [
        "[urdf_spawner-5] process has died [pid PID, exit code 1, cmd gazebo_ros/spawn_model "
        "-urdf -model mrobot -param robot_description __name:=urdf_spawner "
        "__log:=LOG/RUN/urdf_spawner-5.log].",
        "log file: LOG/RUN/urdf_spawner-5*.log",
    ]
    # the node's error is in its log file too
    (log,) = own_log_dir.glob("*/urdf_spawner-5.log")
    assert "SpawnModel: Failure - model name mrobot already exist." in log.read_text()
    messages = _documents(done.stdout)
    odom = messages["/odom"]
    start, end = (o["pose"]["pose"]["position"]["x"] for o in (odom[0], odom[-1]))
    assert abs(start + 1.0) < 0.01  # where the room holds it
    assert end - start > 0.3  # driven forward, as /cmd_vel asks
    scans = messages["/scan"]
    assert scans
    assert scans[-1]["header"]["frame_id"] == "laser_link"
    walls = [r for r in scans[-1]["ranges"] if r is not None and 0.1 < r < 6.0]
    assert len(walls) > 300  # the room's walls, all around


def test_the_lines_and_exit_status_are_debian_roslaunchs(
    tmp_path: Path, endpoint: str, own_log_dir: Path
) -> None:
    """The same launch under Debian's roslaunch (its own roscore on a port of its own, as
    belvedere's launch makes its own graph) and under belvedere: the same lifecycle lines,
    once the run's own parts are masked, and the same exit status."""
    why = missing_debian_ros("rospy", ROSLAUNCH)
    if why is not None:
        pytest.skip(why)
    runs: list[tuple[int, set[str]]] = []
    for side in ("ros", "belvedere"):
        root = tmp_path / side
        launch = life_package(root)
        logs = root / "logs"
        env = {**os.environ, "ROS_PACKAGE_PATH": str(root), "ROS_LOG_DIR": str(logs)}
        if side == "ros":
            port = free_port()
            env |= {
                "PATH": "/usr/bin:" + env.get("PATH", ""),
                "ROS_HOME": str(root / "home"),
                "ROS_MASTER_URI": f"http://127.0.0.1:{port}/",
            }
            argv = [str(ROSLAUNCH), "-p", str(port), str(launch)]
            done = subprocess.run(
                argv, capture_output=True, text=True, env=env, timeout=5 * DEADLINE, check=False
            )
        else:
            done = belvedere_launch(launch, env)
        output = (done.stdout + done.stderr).replace(str(root), "ROOT")
        runs.append((done.returncode, set(lifecycle_lines(output, Path("ROOT/logs")))))
    (ros_code, ros_lines), (our_code, our_lines) = runs
    assert our_code == ros_code == 0
    assert our_lines == ros_lines
    assert "Initiating shutdown!" in ros_lines


WATCH = """#!/usr/bin/env python3
import glob, os, time
import rospy
rospy.init_node("watch")
pattern = os.path.join(os.environ["ROS_LOG_DIR"], "*", rospy.myargv()[1])
while sum(open(p).read().count("error:") for p in glob.glob(pattern)) < 2:
    time.sleep(0.05)
"""

IN_PROCESS = """<launch>
  <include file="$(find gazebo_ros)/launch/empty_world.launch">
    <arg name="gui" value="false"/>
  </include>
  <param name="robot_description" textfile="$(find mbot_description)/urdf/urdf/mbot_base.urdf"/>
  <node name="urdf_spawner" pkg="gazebo_ros" type="spawn_model"
        args="-urdf -model r -param robot_description"/>
  <node pkg="map_server" type="map_server" name="mapless" args="{missing}" respawn="true"/>
  <node pkg="life" type="watch.py" name="boss" args="mapless-4.log" required="true"/>
</launch>
"""
"""Nodes of belvedere's own: the spawner ends once the robot is in; a map server without its
map dies at each start and is started again (its log file keeps each death's error); a
script ends the launch, required, once the map server has died twice."""


def test_nodes_of_this_process_live_and_die_as_processes(
    tmp_path: Path, endpoint: str, own_log_dir: Path
) -> None:
    launch = life_package(tmp_path)
    watch = launch.parent / "scripts" / "watch.py"
    watch.write_text(WATCH)
    watch.chmod(0o755)
    missing = tmp_path / "none.yaml"
    launch.write_text(IN_PROCESS.format(missing=missing))
    env = {**os.environ, "ROS_PACKAGE_PATH": f"{tmp_path}:{EXAMPLES}"}
    done = belvedere_launch(launch, env)
    assert done.returncode == 0, done.stderr
    lines = lifecycle_lines(done.stderr, own_log_dir)
    assert "[urdf_spawner-3] process has finished cleanly" in lines
    died = (
        "[mapless-4] process has died [pid PID, exit code 1, cmd map_server/map_server "
        f"{missing} __name:=mapless __log:=LOG/RUN/mapless-4.log]."
    )
    assert lines.count(died) >= 2
    assert lines[lines.index(died) + 1 : lines.index(died) + 3] == [
        "log file: LOG/RUN/mapless-4*.log",
        "[mapless-4] restarting process",
    ]
    assert "process[mapless-4]: started in this process" in done.stderr
    banner = lines.index("=" * 80 + "REQUIRED process [boss-5] has died!")
    assert lines[banner + 1] == "process has finished cleanly"
    (log,) = own_log_dir.glob("*/mapless-4.log")
    assert log.read_text().count(f"error: cannot read the map file '{missing}'") >= 2


def test_respawn_and_required_together_are_refused_as_roslaunch_refuses_them(
    tmp_path: Path,
) -> None:
    launch = tmp_path / "both.launch"
    launch.write_text(
        '<launch>\n  <node pkg="life" type="hold.py" name="h" respawn="true" required="true"/>\n'
        "</launch>\n"
    )
    done = subprocess.run(
        [*BELVEDERE, "launch", str(launch), "--nodes"], capture_output=True, text=True
    )
    assert done.returncode == 1
    assert done.stderr.startswith(
        f"{launch}:2:3: error: Invalid <node> tag: respawn and required cannot both be set "
        "to true\n"
    )


def test_a_node_whose_run_raises_dies_alone(
    tmp_path: Path, own_log_dir: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """A node of this process raising while it runs (here a timer of its) is that process
    dying with exit code 1; the others run on."""
    launch = tmp_path / "two.launch"
    launch.write_text(
        "<launch>\n"
        '  <node pkg="tf2_ros" type="static_transform_publisher" name="a"\n'
        '        args="0 0 0 0 0 0 m a"/>\n'
        '  <node pkg="tf2_ros" type="static_transform_publisher" name="b"\n'
        '        args="0 0 0 0 0 0 m b"/>\n'
        "</launch>\n"
    )
    packages = PackageIndex([EXAMPLES])
    graph = Graph()
    runtime = LaunchRuntime(
        load_launch(launch, packages=packages), graph, packages, headless=True, lifecycle=True
    )
    runtime.start()
    (_, a), (_, b) = runtime.in_process

    def broken() -> None:
        msg = "a bug in the node"
        raise RuntimeError(msg)

    a.timer(0.1, broken)
    try:
        graph.run(duration=0.5)
        assert runtime.poll_processes() is None  # the launch runs on
    finally:
        runtime.close()
        graph.shutdown()
    assert a.closed
    assert not b.closed
    assert "RuntimeError: a bug in the node" in caplog.text
    assert "[a-2] process has died [pid " in caplog.text
    assert ", exit code 1, cmd tf2_ros/static_transform_publisher 0 0 0 0 0 0 m a " in caplog.text


SPAWNER = """<launch>
  <param name="robot_description" textfile="$(find mbot_description)/urdf/urdf/mbot_base.urdf"/>
  <node name="urdf_spawner" pkg="gazebo_ros" type="spawn_model"
        args="-urdf -model mrobot -param robot_description"/>
</launch>
"""


def test_a_spawner_beside_the_running_room_dies_and_its_launch_ends(
    tmp_path: Path, endpoint: str, own_log_dir: Path
) -> None:
    """In a second terminal, beside the room that holds mrobot: the spawner's launch joins
    the running graph (roslaunch beside a running master); Gazebo refuses the name, the
    spawner dies, and with no process left the launch ends, as roslaunch does."""
    room = [*BELVEDERE, "launch", "--package-path", str(EXAMPLES), "--headless", "mbot_gazebo"]
    room += ["view_mbot_gazebo_room.launch", "gui:=false"]
    spawner = tmp_path / "spawner.launch"
    spawner.write_text(SPAWNER)
    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    with subprocess.Popen(room, **quiet) as running:  # type: ignore[call-overload]
        try:
            wait_until(lambda: graph_running() or running.poll() is not None, what="the graph")
            probe = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint))
            models: list[list[str]] = []
            probe.create_node("probe").subscribe(
                "/gazebo/model_states", "gazebo_msgs/ModelStates", lambda m: models.append(m.name)
            )
            probe.start()
            try:
                wait_until(lambda: models or running.poll() is not None, what="the room")
            finally:
                probe.shutdown()
            assert "mrobot" in models[-1]
            second = [*BELVEDERE, "launch", "--package-path", str(EXAMPLES), str(spawner)]
            done = subprocess.run(
                [*second, "--headless"], capture_output=True, text=True, timeout=DEADLINE
            )
            assert running.poll() is None  # the world runs on
        finally:
            running.terminate()
            running.wait(timeout=DEADLINE)
    assert done.returncode == 0, done.stderr
    assert "SpawnModel: Failure - model name mrobot already exist." in done.stderr
    lines = lifecycle_lines(done.stderr, own_log_dir)
    assert lines[0].startswith(
        "[urdf_spawner-1] process has died [pid PID, exit code 1, cmd gazebo_ros/spawn_model "
    )
    assert "all processes on machine have died, roslaunch will exit" in done.stderr


HOLD_MARKED = """#!/usr/bin/env python3
import os, sys
import rospy
rospy.init_node("hold")
with open(rospy.myargv()[1], "w") as f:
    f.write(str(os.getpid()))
rospy.spin()
"""

HELD = """<launch>
  <node pkg="life" type="hold_marked.py" name="holder" args="{work}/holder.pid"/>
</launch>
"""


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP, signal.SIGINT])
def test_a_launch_ended_by_a_signal_ends_its_scripts(
    tmp_path: Path, endpoint: str, own_log_dir: Path, signum: int
) -> None:
    """``kill`` (SIGTERM), a closed terminal (SIGHUP) and Ctrl-C end a launch as roslaunch
    ends: its scripts' processes end with it, none is left running without it."""
    pkg = tmp_path / "life"
    (pkg / "scripts").mkdir(parents=True)
    (pkg / "package.xml").write_text(PACKAGE_XML)
    script = pkg / "scripts" / "hold_marked.py"
    script.write_text(HOLD_MARKED)
    script.chmod(0o755)
    launch = pkg / "held.launch"
    launch.write_text(HELD.format(work=tmp_path))
    env = {**os.environ, "ROS_PACKAGE_PATH": str(tmp_path)}
    mark = tmp_path / "holder.pid"
    with subprocess.Popen(
        [*BELVEDERE, "launch", str(launch), "--headless"],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    ) as running:
        try:
            wait_until(
                lambda: (mark.is_file() and mark.read_text() != "") or running.poll() is not None,
                what="the script's pid",
            )
            assert running.poll() is None, running.stderr.read() if running.stderr else ""
            holder = int(mark.read_text())
            running.send_signal(signum)
            running.wait(timeout=DEADLINE)
        finally:
            if running.poll() is None:
                running.kill()
    wait_until(lambda: not Path(f"/proc/{holder}").exists(), what="the script's end")
