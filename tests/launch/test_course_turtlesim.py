"""The course's turtlesim chapters end to end, as a learner runs them: ``belvedere launch`` or
``belvedere run turtlesim turtlesim_node`` in one terminal, the learner's rospy scripts
(examples/learning_*) in others, on a graph of this test's own.

The scripts are processes that keep real time, so these runs are paced at real time; what is
asserted is geometry that does not depend on when a message arrived."""

from __future__ import annotations

import itertools
import math
import signal
import subprocess
import sys
import threading
from collections.abc import Iterator
from typing import Any

import pytest

from belvedere.graph import Graph, ZenohTransport
from belvedere.sim.turtlesim import PERIOD, SIZE
from tests.conftest import EXAMPLES
from tests.terminal import Terminal
from tests.waiting import DEADLINE, wait_until

BELVEDERE = [sys.executable, "-m", "belvedere"]
PACKAGES = ["--package-path", str(EXAMPLES)]


class _Watcher:
    """A graph in this process beside the learner's: the turtles' poses as they come."""

    def __init__(self, endpoint: str) -> None:
        self.graph = Graph(
            sim_time=False, transport=ZenohTransport(endpoint=endpoint, serve_params=False)
        )
        self.node = self.graph.create_node("watcher")
        self.poses: dict[str, list[Any]] = {"turtle1": [], "turtle2": []}
        for name, seen in self.poses.items():
            self.node.subscribe(f"/{name}/pose", "turtlesim/Pose", seen.append, queue_size=0)
        self.graph.start(rtf=None)


def _start(verb: str, *words: str) -> subprocess.Popen[str]:
    """``belvedere VERB --headless WORDS`` in the background; its stderr kept for the end."""
    return subprocess.Popen(
        [*BELVEDERE, verb, "--headless", *words],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )


@pytest.fixture
def turtlesim(endpoint: str) -> Iterator[_Watcher]:
    sim = _start("run", "turtlesim", "turtlesim_node")
    watcher = _Watcher(endpoint)
    try:
        wait_until(lambda: watcher.poses["turtle1"], what="turtlesim's /turtle1/pose")
        yield watcher
    finally:
        watcher.graph.shutdown()
        sim.terminate()
        _, err = sim.communicate(timeout=DEADLINE)
    assert "Traceback" not in err, err


def _run(*words: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [*BELVEDERE, "run", *PACKAGES, *words],
        capture_output=True,
        text=True,
        timeout=DEADLINE,
        check=False,
    )


def test_the_velocity_publisher_drives_turtle1_in_turtlesims_circle(
    turtlesim: _Watcher,
) -> None:
    script = subprocess.Popen(
        [*BELVEDERE, "run", *PACKAGES, "learning_topic", "velocity_publisher.py"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    poses = turtlesim.poses["turtle1"]
    try:
        wait_until(
            lambda: sum(p.linear_velocity > 0 for p in poses) > 150,
            what="turtle1 driving for 150 updates",
        )
    finally:
        script.terminate()
        script.wait(timeout=DEADLINE)
    moving = [p for p in poses if p.linear_velocity > 0]
    v, w = 0.5, 0.2
    assert all((p.linear_velocity, p.angular_velocity) == pytest.approx((v, w)) for p in moving)
    # each update turns by w·dt, then moves v·dt along the new heading (float32 on the wire)
    steps = 0
    for before, after in itertools.pairwise(moving):
        theta = before.theta + w * PERIOD
        want = (before.x + math.cos(theta) * v * PERIOD, before.y + math.sin(theta) * v * PERIOD)
        assert (after.x, after.y, after.theta) == pytest.approx((*want, theta), abs=2e-5)
        steps += 1
    assert steps >= 150
    # so the turtle is on the circle of radius v/w through its start, centred to its left
    radius = v / w
    centre = (SIZE / 2, SIZE / 2 + radius)
    for p in moving:
        assert math.hypot(p.x - centre[0], p.y - centre[1]) == pytest.approx(radius, abs=0.01)


def test_spawn_and_the_background_parameters(turtlesim: _Watcher) -> None:
    spawned = _run("learning_service", "turtle_spawn.py")
    assert spawned.returncode == 0, spawned.stderr
    assert "Spawn turtle successfully [name:turtle2]" in spawned.stdout
    seen = wait_until(lambda: turtlesim.poses["turtle2"], what="/turtle2/pose")
    assert (seen[-1].x, seen[-1].y) == pytest.approx((2.0, 2.0))
    again = _run("learning_service", "turtle_spawn.py")
    assert again.returncode == 1  # the name is taken: turtlesim answers with an error
    assert "Service call failed" in again.stdout

    colours: list[Any] = []
    turtlesim.node.subscribe("/turtle1/color_sensor", "turtlesim/Color", colours.append)
    wait_until(lambda: colours, what="/turtle1/color_sensor")
    assert (colours[-1].r, colours[-1].g, colours[-1].b) == (69, 86, 255)
    config = _run("learning_parameter", "parameter_config.py")
    assert config.returncode == 0, config.stderr
    assert "Get Background Color[69, 86, 255]" in config.stdout
    assert "Re-get Background Color[255, 255, 255]" in config.stdout
    wait_until(
        lambda: (colours[-1].r, colours[-1].g, colours[-1].b) == (255, 255, 255),
        what="the background white after /clear",
    )


def test_the_tf_demo_turtle2_catches_turtle1(endpoint: str) -> None:
    launch = _start("launch", *PACKAGES, "learning_tf", "start_tf_demo_py.launch")
    watcher = _Watcher(endpoint)
    try:
        wait_until(lambda: watcher.poses["turtle2"], what="turtle2, spawned by the listener")
        start = watcher.poses["turtle2"][0]
        assert (start.x, start.y) == pytest.approx((4.0, 2.0))

        def gap() -> float:
            one, two = watcher.poses["turtle1"][-1], watcher.poses["turtle2"][-1]
            return math.hypot(one.x - two.x, one.y - two.y)

        assert gap() > 3.5
        wait_until(lambda: gap() < 0.2, what="turtle2 next to turtle1", detail=gap)
    finally:
        watcher.graph.shutdown()
        launch.send_signal(signal.SIGINT)  # Ctrl-C: roslaunch ends its script nodes too
        _, err = launch.communicate(timeout=DEADLINE)
    assert err.endswith("done\n"), err  # roslaunch's last word after a clean shutdown


def test_turtle_teleop_key_drives_turtle1_from_a_terminal(turtlesim: _Watcher) -> None:
    terminal = Terminal()
    teleop = subprocess.Popen(
        [*BELVEDERE, "run", "turtlesim", "turtle_teleop_key"],
        stdin=terminal.slave,
        stdout=terminal.slave,
        stderr=subprocess.DEVNULL,
    )
    poses = turtlesim.poses["turtle1"]
    try:
        terminal.wait_for("Use arrow keys to move the turtle. 'q' to quit.")
        start = poses[-1]
        terminal.type("\x1b[A")  # up: 2.0 m/s for turtlesim's second
        wait_until(lambda: poses[-1].linear_velocity == 2.0, what="turtle1 driving")
        wait_until(lambda: poses[-1].linear_velocity == 0.0, what="turtle1 stopping after 1 s")
        # 62 or 63 updates of 2.0 m/s x 16 ms, depending on where the second fell
        assert poses[-1].x - start.x == pytest.approx(2.0, abs=0.05)
        terminal.type("\x1b[D")  # left: 2.0 rad/s
        wait_until(lambda: poses[-1].angular_velocity == 2.0, what="turtle1 turning")
        terminal.type("q")
        assert teleop.wait(timeout=DEADLINE) == 0
    finally:
        if teleop.poll() is None:
            teleop.kill()
            teleop.wait(timeout=DEADLINE)
        terminal.close()


def test_the_pose_subscriber_logs_where_turtle1_is(turtlesim: _Watcher) -> None:
    del turtlesim
    script = subprocess.Popen(
        [*BELVEDERE, "run", *PACKAGES, "learning_topic", "pose_subscriber.py"],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    lines: list[str] = []
    out = script.stdout
    assert out is not None
    reader = threading.Thread(target=lambda: lines.extend(iter(out.readline, "")))
    reader.start()
    try:
        wait_until(lambda: any("Turtle pose" in line for line in lines), what="a pose logged")
    finally:
        script.terminate()
        script.wait(timeout=DEADLINE)
        reader.join(timeout=DEADLINE)
    logged = next(line for line in lines if "Turtle pose" in line)
    assert logged.rstrip().endswith("Turtle pose: x:5.544445, y:5.544445")  # float32
