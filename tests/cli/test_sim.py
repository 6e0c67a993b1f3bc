"""``belvedere sim --engine kinematic``: scripted runs and their errors."""

from __future__ import annotations

import socket
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from belvedere.cli import main
from belvedere.graph import Graph, ZenohTransport
from tests.conftest import EXAMPLES
from tests.waiting import DEADLINE, wait_until

MBOT = str(EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_gazebo.xacro")
MBOT_YAML = str(EXAMPLES / "mbot_description/config/fake_mbot_arbotix.yaml")
TURTLEBOT = str(EXAMPLES / "rbx1_description/urdf/turtlebot.urdf.xacro")
RBX1_YAML = str(EXAMPLES / "rbx1_bringup/config/fake_turtlebot_arbotix.yaml")
CIRCLE = "/cmd_vel geometry_msgs/Twist {linear: {x: 0.2}, angular: {z: 0.5}}"


def _documents(text: str) -> list[dict[str, object]]:
    return [yaml.safe_load(d) for d in text.split("\n---\n") if d.strip()]


def test_scripted_run_prints_odometry(endpoint: str, capsys: pytest.CaptureFixture[str]) -> None:
    args = ["sim", MBOT, "--engine", "kinematic", "--config", MBOT_YAML, "--headless"]
    args += ["--rtf", "max", "--duration", "10", "--pub", CIRCLE, "--echo", "/odom"]
    assert main(args) == 0
    out, err = capsys.readouterr()
    odom = _documents(out)
    assert len(odom) == 100
    last = odom[-1]
    # arbotix_python is a rospy node: header.seq counts the messages sent, from 1
    assert last["header"] == {"seq": 100, "stamp": {"secs": 10, "nsecs": 0}, "frame_id": "odom"}
    assert last["child_frame_id"] == "base_footprint"
    position = last["pose"]["pose"]["position"]  # type: ignore[index]
    x, y = position["x"], position["y"]
    assert abs(((x**2 + (y - 0.4) ** 2) ** 0.5) - 0.4) < 0.0101
    assert "simulated 10 s in" in err
    # Deterministic: a second run prints the same bytes.
    assert main(args) == 0
    assert capsys.readouterr().out == out


def test_rbx1_fake_turtlebot_in_one_command(
    endpoint: str, capsys: pytest.CaptureFixture[str]
) -> None:
    args = ["sim", TURTLEBOT, "--config", RBX1_YAML, "--headless", "--rtf", "max"]
    args += ["--duration", "1", "--pub", "/cmd_vel geometry_msgs/Twist {linear: {x: 0.1}}"]
    args += ["--echo", "/odom", "--echo", "/joint_states"]
    assert main(args) == 0
    out = capsys.readouterr().out
    blocks = [b for b in out.split("\n---\n") if b.strip()]
    odom = [yaml.safe_load(b) for b in blocks if b.startswith("# /odom")]
    states = [yaml.safe_load(b) for b in blocks if b.startswith("# /joint_states")]
    assert len(odom) == 10
    assert odom[-1]["pose"]["pose"]["position"]["x"] == pytest.approx(0.1)
    # joint_states from the driver (20 Hz: its wheels, which are the model's drive joints, as
    # in rbx1's TurtleBot) and joint_state_publisher (10 Hz: no joint left for it).
    names = {tuple(s["name"]) for s in states}
    assert names == {("base_l_wheel_joint", "base_r_wheel_joint"), ()}
    assert len(states) == 20 + 10


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--pub", "/cmd_vel geometry_msgs/Twist {linear: [}"], "is not valid YAML at column 11"),
        (["--pub", "/cmd_vel"], "--pub expects 'TOPIC TYPE YAML'"),
        (
            ["--pub", "/cmd_vel geometry_msgs/Twst {}"],
            "--pub '/cmd_vel geometry_msgs/Twst {}': unknown",
        ),
        (["--echo", "/nothing"], "--echo /nothing: no node in this run"),
        (["--duration", "-1"], "--duration expects a positive number"),
        (["no_such:=arg", "extra"], "unexpected arguments: extra"),
    ],
)
def test_bad_arguments_are_one_clear_error(
    endpoint: str, capsys: pytest.CaptureFixture[str], extra: list[str], message: str
) -> None:
    assert main(["sim", MBOT, "--headless", "--rtf", "max", "--duration", "1", *extra]) == 1
    err = capsys.readouterr().err
    assert message in err
    assert "Traceback" not in err


def test_bad_config_names_the_line(
    endpoint: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = tmp_path / "fake.yaml"
    bad.write_text("controllers:\n  base_controller:\n    type: diff_controller\n")
    assert main(["sim", MBOT, "--config", str(bad), "--headless", "--duration", "1"]) == 1
    err = capsys.readouterr().err
    assert f"{bad}:3:5: error: controllers/base_controller: required parameter" in err


def test_rtf_must_be_positive_or_max(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["sim", MBOT, "--rtf", "0"]) == 2
    assert "--rtf expects a positive number or 'max'" in capsys.readouterr().err


def test_paced_run_with_the_viewer_and_tools(endpoint: str) -> None:
    """A real process: the viewer serves, another process drives the robot over Zenoh."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    sim = subprocess.Popen(  # paced, until we stop it
        [sys.executable, "-m", "belvedere", "sim", MBOT, "--port", str(port)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    watcher = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint, serve_params=False))
    speeds: list[float] = []
    watcher.create_node("watcher").subscribe(
        "/odom", "nav_msgs/Odometry", lambda m: speeds.append(m.twist.twist.linear.x)
    )
    watcher.start(rtf=None)
    try:
        assert sim.stderr is not None
        line = sim.stderr.readline()
        while line and "viewer: http://127.0.0.1:" not in line:
            line = sim.stderr.readline()
        assert f"viewer: http://127.0.0.1:{port}" in line
        pub = ["topic", "pub", "-1", "/cmd_vel", "geometry_msgs/Twist", "{linear: {x: 1.0}}"]

        def commanded() -> bool:
            # The sim prints the viewer's URL before its base may have subscribed (seen on a
            # busy CI run): a one-shot command is sent again until odometry shows it. The
            # fake base keeps its last command: once odometry shows it, every message does.
            assert main(pub) == 0
            return 1.0 in speeds

        wait_until(commanded, what="the sim's /odom to show the command", interval=0.5)
        tool = subprocess.run(
            [sys.executable, "-m", "belvedere", "topic", "echo", "-n", "1", "/odom"],
            capture_output=True,
            text=True,
            timeout=DEADLINE,
            check=True,
        )
        (odom,) = _documents(tool.stdout)
        assert odom["twist"]["twist"]["linear"]["x"] == 1.0  # type: ignore[index]
    finally:
        watcher.shutdown()
        sim.terminate()
        sim.wait(timeout=DEADLINE)


def test_physics_scripted_run_in_a_world(endpoint: str, capsys: pytest.CaptureFixture[str]) -> None:
    world = str(EXAMPLES / "mbot_gazebo/worlds/playground.world")
    args = ["sim", MBOT, "--engine", "physics", "--world", world, "--headless", "--rtf", "max"]
    args += ["--duration", "2", "-x", "0.5", "-Y", "1.5707963"]
    args += ["--pub", "/cmd_vel geometry_msgs/Twist {linear: {x: 0.2}}", "--echo", "/odom"]
    assert main(args) == 0
    out = capsys.readouterr().out
    odom = _documents(out)
    # 100 Hz; Gazebo's "more than one period passed" check puts the first at 11 ms
    assert len(odom) == 199
    position = odom[-1]["pose"]["pose"]["position"]  # type: ignore[index]
    assert position["x"] == pytest.approx(0.5, abs=0.02)  # spawned at x=0.5 facing +y
    assert position["y"] > 0.25


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--world", "/no/such.world"], "cannot read /no/such.world"),
        (["--engine", "physics", "--config", MBOT_YAML], "--config and --namespace are for"),
        (
            ["--engine", "kinematic", "--paused"],
            "error: --world and --paused are for --engine physics, not kinematic",
        ),
    ],
)
def test_physics_argument_errors(
    endpoint: str, capsys: pytest.CaptureFixture[str], extra: list[str], message: str
) -> None:
    engine = [] if "--engine" in extra else ["--engine", "physics"]
    assert main(["sim", MBOT, "--headless", "--duration", "1", *engine, *extra]) == 1
    assert message in capsys.readouterr().err


def test_a_world_implies_the_physics_engine(
    endpoint: str, capsys: pytest.CaptureFixture[str]
) -> None:
    world = str(EXAMPLES / "mbot_gazebo/worlds/empty.world")
    args = ["sim", MBOT, "--world", world, "--headless", "--rtf", "max", "--duration", "0.5"]
    args += ["--echo", "/odom"]
    assert main(args) == 0
    out, err = capsys.readouterr()
    assert [line for line in err.splitlines() if "implies" in line] == [
        "note: --world implies --engine physics"
    ]
    assert "error" not in err
    assert len(_documents(out)) == 49  # the diff-drive plugin's 100 Hz, not ArbotiX's 10
    assert main(["-q", *args]) == 0
    assert "implies" not in capsys.readouterr().err


def test_a_world_that_already_holds_the_robot(
    endpoint: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    world = tmp_path / "saved.world"
    world.write_text(
        "<sdf version='1.7'><world name='default'>\n"
        "  <model name='mbot'><link name='base_footprint'/></model>\n"
        "</world></sdf>\n"
    )
    args = ["sim", MBOT, "--engine", "physics", "--world", str(world), "--headless"]
    assert main([*args, "--duration", "0.1"]) == 1
    err = capsys.readouterr().err
    assert f"{world}:2:3: error: SpawnModel: Failure - model name mbot already exist." in err
    assert "The world already has a model named 'mbot'" in err
    assert "mbot_gazebo.xacro cannot be spawned under that name again" in err


def test_a_paused_run_with_a_duration_ends_once_unpaused(endpoint: str) -> None:
    """--duration is simulated time: a paused simulation says so, and ends after it once
    something unpauses it (here the gazebo_ros service, from another process)."""
    run = [sys.executable, "-m", "belvedere", "sim", MBOT, "--paused", "--headless"]
    with subprocess.Popen([*run, "--duration", "0.5"], stderr=subprocess.PIPE, text=True) as sim:
        try:
            assert sim.stderr is not None
            lines = [sim.stderr.readline() for _ in range(3)]
            assert any(
                "note: paused, --duration counts from when the simulation runs" in line
                for line in lines
            ), lines
            with pytest.raises(subprocess.TimeoutExpired):
                sim.wait(timeout=2.0)  # paused: half a second of its time never passes
            wait_until(
                lambda: (
                    subprocess.run(
                        [
                            sys.executable,
                            "-m",
                            "belvedere",
                            "service",
                            "call",
                            "/gazebo/unpause_physics",
                            "{}",
                        ],
                        capture_output=True,
                        check=False,
                    ).returncode
                    == 0
                ),
                what="the unpause service to answer",
            )
            assert sim.wait(timeout=DEADLINE) == 0
        finally:
            if sim.poll() is None:
                sim.kill()
