"""Recording and playing on the graph: ``belvedere bag record`` of the physics simulation at
``--rtf max`` loses nothing, a killed recording loses at most its last second, durations are
the graph's time, ``bag play`` keeps rosbag's options, and a launch file that plays a bag
(``--clock``) into a recorder gives the same bag on every run."""

from __future__ import annotations

import shutil
import tempfile
import time
from collections import Counter
from functools import partial
from pathlib import Path
from typing import Any

import pytest

from belvedere.bags import (
    BagError,
    Decoder,
    Player,
    PlayOptions,
    Recorder,
    RecordOptions,
    Sample,
    TapRecording,
    open_bag,
    reindex,
)
from belvedere.cli import main
from belvedere.description.urdf import Pose, RobotModel
from belvedere.graph import Graph, ZenohTransport
from belvedere.launch import LaunchError
from belvedere.packages import PackageIndex
from belvedere.sim.physics import GazeboRos, PhysicsSimulation
from belvedere.tf import JointStatePublisher, RobotStatePublisher
from belvedere.world import read_world
from tests.bags._make import MS, write_sample
from tests.conftest import EXAMPLES
from tests.processes import BelvedereProcess
from tests.waiting import DEADLINE, wait_until

LASER_MBOT = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_with_laser_gazebo.xacro"
PLAYGROUND = EXAMPLES / "mbot_gazebo/worlds/playground.world"


class RecorderProcess(BelvedereProcess):
    """``belvedere bag record …`` in a process of its own, on this test's graph."""

    def __init__(self, *args: str, cwd: Path) -> None:
        super().__init__(
            ["bag", "record", *args],
            ready="Recording to",
            ended="the recorder ended before recording",
            cwd=cwd,
        )


def _counts(path: Path) -> Counter[str]:
    bag = open_bag(path)
    counts: Counter[str] = Counter()
    for c in bag.connections:
        counts[c.topic] += bag.counts[c.id]
    bag.close()
    return counts


def _recorded_so_far(active: Path) -> Counter[str]:
    """What a recording holds now: its whole chunks, read from a repaired copy."""
    if not active.exists():
        return Counter()
    with tempfile.TemporaryDirectory() as tmp:
        copy = Path(tmp) / active.name.removesuffix(".active")
        shutil.copyfile(active, copy)
        try:
            reindex(copy)
        except BagError:
            return Counter()
        return _counts(copy)


def _physics_sim(graph: Graph) -> None:
    """What ``belvedere sim --engine physics`` runs: a laser mbot in the playground, its
    plugins, gazebo_ros, robot and joint state publishers, driven in a circle."""
    packages = PackageIndex.from_environment(near=str(LASER_MBOT))
    model = RobotModel.from_path(str(LASER_MBOT), packages=packages)
    sim = PhysicsSimulation(graph, read_world(PLAYGROUND, packages=packages))
    GazeboRos(sim, packages=packages)
    graph.params.set("/robot_description", model.to_urdf())
    robot = sim.spawn(
        model, name=model.name, pose=Pose((0.5, 0.0, 0.0), (0, 0, 0)), packages=packages
    )
    RobotStatePublisher(graph.create_node("robot_state_publisher"), model)
    JointStatePublisher(
        graph.create_node("joint_state_publisher"), model, exclude=robot.published_joints()
    )
    drive = graph.create_node("driver").publisher("/cmd_vel", "geometry_msgs/Twist", latch=True)
    drive.publish_data({"linear": {"x": 0.2}, "angular": {"z": 0.5}})


def test_a_latched_publication_is_recorded_once_however_often_it_comes(endpoint: str) -> None:
    """The recorder hears a latched message through its tap and asks for the latched ones
    when it sees their publisher: the reply can come before or after the tapped copy (CI once
    recorded a latched /cmd_vel twice). A publication is recorded once, a later one too."""
    transport = ZenohTransport(endpoint=endpoint)
    source = TapRecording(transport, Recorder(RecordOptions(all=True)))
    try:
        # what discovering the publisher tells the recorder (its type; that it latches)
        source._types["/cmd_vel"] = "geometry_msgs/msg/Twist"
        source._latching["/cmd_vel"] = True

        def sample(number: int) -> Sample:
            return Sample("/cmd_vel", None, 1, b"twist", True, 1, latch=("driver", number))

        recorded = [
            *source.ready(sample(1)),
            *source.ready(sample(1)),  # the other way
            *source.ready(sample(2)),
            *source.ready(sample(1)),  # an older reply, late
        ]
    finally:
        source.close()
        transport.close()
    assert [s.latch for s in recorded] == [("driver", 1), ("driver", 2)]


@pytest.mark.parametrize("ext", ["bag", "mcap"])
def test_recording_the_physics_simulation_at_full_speed_loses_nothing(
    endpoint: str, tmp_path: Path, ext: str
) -> None:
    recorder = RecorderProcess("-a", "-O", f"sim.{ext}", cwd=tmp_path)
    transport = ZenohTransport()
    graph = Graph(sim_time=True, transport=transport)
    try:
        _physics_sim(graph)
        graph.run(duration=2.0, rtf=None)
        published = {
            name: sum(p.count for p in topic.publishers)
            for name, topic in graph.topics.items()
            if topic.publishers
        }
        sent = {name: s.sent for name, s in transport.stats.items()}
        # the last message: once it is in the recording, so is everything before it
        graph.create_node("end").publisher("/done", "std_msgs/Empty").publish_data({})
        wait_until(
            lambda: _recorded_so_far(tmp_path / f"sim.{ext}.active")["/done"],
            what="the recording to reach the last message",
        )
    finally:
        graph.shutdown()
        log = recorder.stop()
    recorded = _counts(tmp_path / f"sim.{ext}")
    del recorded["/done"]
    assert "Subscribing to /scan" in log
    for topic in ("/clock", "/odom", "/scan", "/tf", "/joint_states", "/gazebo/model_states"):
        assert published[topic] > 0, topic
    # every message published was sent to the recorder and recorded
    assert {t: n for t, n in published.items() if n} == dict(recorded)
    assert {t: sent.get(t, 0) for t in recorded if t != "/tf_static"} == {
        t: n for t, n in recorded.items() if t != "/tf_static"
    }


def test_a_killed_recording_loses_at_most_its_last_second(endpoint: str, tmp_path: Path) -> None:
    graph = Graph(sim_time=False, transport=ZenohTransport())
    node = graph.create_node("counter")
    pub = node.publisher("/count", "std_msgs/UInt32")
    sent: list[tuple[int, int]] = []

    def tick() -> None:
        n = len(sent)
        pub.publish_data({"data": n})
        sent.append((n, time.time_ns()))

    node.timer(0.01, tick)
    recorder = RecorderProcess("/count", "-O", "killed.bag", cwd=tmp_path)
    wait_until(lambda: pub.topic.remote, what="the recorder to subscribe")
    graph.start(rtf=None)
    active = tmp_path / "killed.bag.active"
    try:
        wait_until(lambda: _recorded_so_far(active)["/count"] >= 200, what="two seconds recorded")
        killed_at = time.time_ns()
        recorder.proc.kill()
        recorder.proc.wait(timeout=DEADLINE)
    finally:
        graph.shutdown()
    assert main(["bag", "reindex", str(active)]) == 0
    bag = open_bag(active)
    values = [Decoder().decode(m).data for m in bag.messages()]
    bag.close()
    assert values == list(range(len(values)))  # nothing lost before the end
    published_by_kill = [n for n, at in sent if at <= killed_at]
    lost = len(published_by_kill) - len(values)
    # a chunk is written every second: at 100 Hz at most ~100 are lost (with room for a
    # busy machine's scheduling, as the recorder's thread may wake a little late)
    assert lost <= 150, lost


def test_duration_is_the_graphs_time(endpoint: str, tmp_path: Path) -> None:
    transport = ZenohTransport()
    graph = Graph(sim_time=True, transport=transport)
    node = graph.create_node("ticker")
    pub = node.publisher("/tick", "std_msgs/UInt32")
    count = [0]

    def tick() -> None:
        pub.publish_data({"data": count[0]})
        count[0] += 1

    node.timer(0.02, tick)
    recorder = RecorderProcess("/tick", "--duration", "1", "-O", "short.bag", cwd=tmp_path)
    try:
        ticks, clock = graph.topics["/tick"], graph.topics["/clock"]
        wait_until(lambda: ticks.remote and clock.remote, what="the recorder to subscribe")
        # as fast as it goes: /clock and /tick travel apart, and the clock passing the end
        # must not stop the recording before the ticks stamped within it arrived
        graph.run(duration=3.0, rtf=None)
        _, err = recorder.proc.communicate(timeout=DEADLINE)  # it stops by itself
    finally:
        graph.shutdown()
    assert recorder.proc.returncode == 0, err
    bag = open_bag(tmp_path / "short.bag")
    stamps = [m.stamp_ns for m in bag.messages()]
    bag.close()
    # stamped with the simulated time each tick was published at: one second of 50 Hz
    assert stamps == [20 * MS * (n + 1) for n in range(51)]
    assert "━" not in err  # no progress bar when piped


def test_play_options_on_the_graph(endpoint: str, tmp_path: Path) -> None:
    path = tmp_path / "sample.bag"
    write_sample(path)
    graph = Graph(sim_time=False, transport=ZenohTransport())
    got: list[int] = []
    graph.create_node("listener").subscribe(
        "/robot1/odom", "nav_msgs/Odometry", lambda m: got.append(m.header.seq), queue_size=0
    )
    graph.start(rtf=None)
    try:
        args = ["bag", "play", str(path), "-r", "20", "-s", "0.5", "-u", "1.0", "-p", "/robot1"]
        args += ["--topics", "/odom", "--wait-for-subscribers", "-d", "0"]
        assert main(args) == 0
        wait_until(lambda: len(got) >= 100, what="100 odometry messages", detail=lambda: len(got))
    finally:
        graph.shutdown()
    # -s 0.5 -u 1.0 from the first message (5 ms): stamps 505 ms … 1505 ms
    assert got == list(range(50, 150))


def _note(into: list[tuple[int, str]], graph: Graph, what: str, msg: Any) -> None:
    into.append((graph.now_ns(), what))


def test_player_loop_pause_and_immediate() -> None:
    path = Path(tempfile.mkdtemp()) / "sample.mcap"
    write_sample(path)
    graph = Graph(sim_time=True)
    seen: list[tuple[int, str]] = []
    node = graph.create_node("listener")
    for topic, kind in (("/odom", "nav_msgs/Odometry"), ("/scan", "sensor_msgs/LaserScan")):
        node.subscribe(topic, kind, partial(_note, seen, graph, topic), queue_size=0)
    player = Player(
        graph.create_node("play"),
        PlayOptions(bags=(path,), loop=True, topics=frozenset({"/odom"}), rate=2.0),
    )
    player.start()
    graph.run(duration=2.5, rtf=None)
    # at twice the speed one pass (5 ms … 2 s of bag) takes ~1 s of graph time: 2.5 passes
    assert 490 <= len(seen) <= 510
    assert {t for _, t in seen} == {"/odom"}
    assert not player.done.is_set()

    seen.clear()
    graph = Graph(sim_time=True)
    node = graph.create_node("listener")
    node.subscribe("/odom", "nav_msgs/Odometry", partial(_note, seen, graph, "o"), queue_size=0)
    node.subscribe("/scan", "sensor_msgs/LaserScan", partial(_note, seen, graph, "s"), queue_size=0)
    player = Player(
        graph.create_node("play"), PlayOptions(bags=(path,), pause_topics=frozenset({"/scan"}))
    )
    player.start()
    graph.run(duration=5.0, rtf=None)
    assert player.paused
    assert [t for _, t in seen].count("s") == 1  # paused after the first scan (at 100 ms)
    assert len(seen) == 11
    player.step()  # one more message
    graph.spin_once()
    assert len(seen) == 12
    player.pause(False)
    graph.run(duration=5.0, rtf=None)
    assert [t for _, t in seen].count("s") == 2

    seen.clear()
    graph = Graph(sim_time=True)
    graph.create_node("l").subscribe(
        "/odom", "nav_msgs/Odometry", partial(_note, seen, graph, "o"), queue_size=0
    )
    player = Player(graph.create_node("play"), PlayOptions(bags=(path,), immediate=True))
    player.start()
    graph.run(rtf=None, until=player.done.is_set)
    assert len(seen) == 200
    assert {when for when, _ in seen} == {0}


def test_latched_topics_reach_late_subscribers(tmp_path: Path) -> None:
    path = tmp_path / "sample.bag"
    write_sample(path)
    graph = Graph(sim_time=True)
    player = Player(graph.create_node("play"), PlayOptions(bags=(path,), clock=True))
    player.start()
    graph.run(rtf=None, until=player.done.is_set)
    late: list[Any] = []
    graph.create_node("late").subscribe("/map_name", "std_msgs/String", late.append)
    graph.spin_once()
    assert [m.data for m in late] == ["cloister"]
    assert graph.now_ns() == 2000 * MS  # the graph's time is the bag's: its last message


LAUNCH = """<launch>
  <node pkg="rosbag" type="play" name="player" required="true" args="--clock {bag}"/>
  <node pkg="rosbag" type="record" name="recorder" args="-a -x /clock -O {out}"/>
</launch>
"""


def test_a_launch_playing_into_a_recorder_is_deterministic(
    endpoint: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    source = tmp_path / "source.bag"
    write_sample(source, flush_every=50)
    runs = []
    for run in range(2):
        out = tmp_path / f"out{run}.mcap"
        launch = tmp_path / f"replay{run}.launch"
        launch.write_text(LAUNCH.format(bag=source, out=out))
        assert main(["launch", str(launch), "--headless", "--rtf", "max"]) == 0
        bag = open_bag(out)
        runs.append([(m.connection.topic, m.stamp_ns, m.data) for m in bag.messages()])
        bag.close()
    err = capsys.readouterr().err
    assert "REQUIRED process [player-2] has died!\nprocess has finished cleanly\n" in err
    assert runs[0] == runs[1]
    original = open_bag(source)
    expected = [(m.connection.topic, m.stamp_ns) for m in original.messages()]
    original.close()
    # recorded at the graph's time, which is the bag's: every message where it was
    assert [(t, s) for t, s, _ in runs[0]] == expected


def test_rosbag_nodes_report_bad_arguments_at_their_line(tmp_path: Path) -> None:
    launch = tmp_path / "bad.launch"
    launch.write_text(
        '<launch>\n  <node pkg="rosbag" type="record" name="r" args="-a --bz2 --lz4"/>\n</launch>\n'
    )
    from belvedere.launch import load_launch
    from belvedere.launch._runtime import LaunchRuntime

    config = load_launch(str(launch), packages=PackageIndex.from_environment())
    runtime = LaunchRuntime(config, Graph(sim_time=True), PackageIndex.from_environment())
    with pytest.raises(LaunchError) as caught:
        runtime.start()
    assert caught.value.location is not None
    assert caught.value.location.line == 2
    assert "cannot use both --bz2 and --lz4" in caught.value.message


def _ticking_graph(topics: dict[str, float]) -> Graph:
    """A simulated-time graph publishing a counter on each topic at its rate (Hz)."""
    graph = Graph(sim_time=True)
    node = graph.create_node("ticker")
    for topic, hz in topics.items():
        pub = node.publisher(topic, "std_msgs/UInt32")
        count = [0]

        def tick(pub: Any = pub, count: list[int] = count) -> None:
            pub.publish_data({"data": count[0]})
            count[0] += 1

        node.timer(1.0 / hz, tick)
    return graph


def test_split_by_duration_keeps_the_newest_files(tmp_path: Path) -> None:
    from belvedere.bags import GraphRecording, Recorder, parse_record_args

    graph = _ticking_graph({"/a": 50.0, "/b": 10.0})
    options = parse_record_args(
        ["-a", "--split", "--duration", "1", "--max-splits", "2", "-O", "part.mcap"]
    )
    recorder = Recorder(options, directory=tmp_path)
    recorder.start(GraphRecording(graph.create_node("record"), recorder))
    graph.run(duration=3.5, rtf=None)
    recorder.stop()
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["part_2.mcap", "part_3.mcap"]  # _0 and _1 were erased
    bag = open_bag(tmp_path / "part_2.mcap")
    stamps = [m.stamp_ns for m in bag.messages()]
    bag.close()
    assert stamps[0] > 2 * 10**9
    assert stamps[-1] - stamps[0] <= 10**9
    assert _counts(tmp_path / "part_3.mcap")["/a"] > 0


def test_limit_per_topic_ends_the_recording(tmp_path: Path) -> None:
    from belvedere.bags import GraphRecording, Recorder, parse_record_args

    graph = _ticking_graph({"/a": 50.0, "/b": 10.0})
    recorder = Recorder(parse_record_args(["/a", "/b", "-l", "5", "-O", "few"]), directory=tmp_path)
    recorder.start(GraphRecording(graph.create_node("record"), recorder))
    graph.run(duration=2.0, rtf=None)
    wait_until(recorder.finished.is_set, what="the limits to end the recording")
    recorder.stop()
    assert _counts(tmp_path / "few.bag") == Counter({"/a": 5, "/b": 5})


def test_a_full_disk_is_one_error(full_disk: Path) -> None:
    from belvedere.bags import GraphRecording, Recorder, parse_record_args

    graph = _ticking_graph({"/a": 1000.0})
    recorder = Recorder(parse_record_args(["-a", "-O", "x.bag"]), directory=full_disk)
    recorder.start(GraphRecording(graph.create_node("record"), recorder))
    graph.run(duration=10.0, rtf=None)  # ~300 KB of messages for a 64 KiB disk
    wait_until(recorder.finished.is_set, what="the recording to fail")
    with pytest.raises(BagError) as caught:
        recorder.stop()
    assert caught.value.message.startswith(f"cannot write {full_disk / 'x.bag.active'}: ")
    assert "No space left on device" in caught.value.message
