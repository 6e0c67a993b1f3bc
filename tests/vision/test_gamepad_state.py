"""A gamepad's state from a browser page, checked before use (numbers, bounded lengths, a
button 0 or 1), the viewer's State field read and its status line shown as plain text, and
joy_node's publishing of states: signs and dead zone, ``~coalesce_interval`` and
``~autorepeat_rate`` in simulated time."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from belvedere.graph import Graph
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.msgs import (
    GAMEPAD_TOPIC,
    GAMEPAD_TYPE,
    GamepadState,
    gamepad_from_json,
    gamepad_from_msg,
    gamepad_state,
)
from belvedere.nodes.joy import JoyPublisher
from belvedere.packages import PackageIndex
from belvedere.viewer._gamepad import NO_PAD, pad_markdown, parse_field
from tests.conftest import free_port

PAD = GamepadState("pad", (0.0, -0.55), (1, 0))


def test_a_state_the_page_sends_is_read() -> None:
    text = json.dumps({"id": "Xbox 360 Controller", "axes": [0.5, -2, 1], "buttons": [0, 1]})
    assert gamepad_from_json(text) == GamepadState("Xbox 360 Controller", (0.5, -1.0, 1.0), (0, 1))
    assert gamepad_from_json('{"axes": [], "buttons": []}') == GamepadState("", (), ())


@pytest.mark.parametrize(
    "text",
    [
        "not json",
        "[1, 2]",
        '{"axes": [0.1]}',  # no buttons
        '{"axes": "0.1", "buttons": []}',
        '{"axes": [NaN], "buttons": []}',
        '{"axes": [Infinity], "buttons": []}',
        '{"axes": [true], "buttons": []}',
        '{"axes": ["0.1"], "buttons": []}',
        '{"axes": [], "buttons": [2]}',
        '{"axes": [], "buttons": [true]}',
        '{"axes": [], "buttons": [0.5]}',
        '{"id": 7, "axes": [], "buttons": []}',
        json.dumps({"axes": [0.0] * 65, "buttons": []}),
        json.dumps({"axes": [], "buttons": [0] * 129}),
        json.dumps({"id": "x" * 20_000, "axes": [], "buttons": []}),
    ],
)
def test_what_is_not_a_state_is_refused(text: str) -> None:
    assert gamepad_from_json(text) is None


def test_a_long_id_is_cut() -> None:
    state = gamepad_state("p" * 1000, [], [])
    assert state is not None
    assert len(state.id) == 200


def test_the_viewer_field_is_read() -> None:
    assert parse_field("gamepad:") == (True, None)
    assert parse_field('gamepad:{"id": "pad", "axes": [0], "buttons": [1]}') == (
        True,
        GamepadState("pad", (0.0,), (1,)),
    )
    assert parse_field('{"id": "pad", "axes": [0], "buttons": [1]}') == (False, None)
    assert parse_field("gamepad:{oops") == (False, None)


def test_the_status_line_shows_the_id_as_text() -> None:
    assert pad_markdown(None) == NO_PAD
    shown = pad_markdown(GamepadState("<img src=x onerror=alert(1)> **pad**\n", (), ()))
    assert shown == r"Gamepad: \<img src\=x onerror\=alert\(1\)\> \*\*pad\*\*"
    assert pad_markdown(GamepadState("Logitech F310 (Vendor: 046d)", (), ())) == (
        r"Gamepad: Logitech F310 \(Vendor\: 046d\)"
    )


def _joy(params: dict[str, Any]) -> tuple[Graph, JoyPublisher, list[Any]]:
    graph = Graph()
    for name, value in params.items():
        graph.params.set(f"/joy_node/{name}", value)
    node = graph.create_node("joy_node")
    joy = JoyPublisher(
        node,
        deadzone=0.1,
        autorepeat_rate=float(params.get("autorepeat_rate", 0.0)),
        coalesce_interval=float(params.get("coalesce_interval", 0.001)),
    )
    received: list[Any] = []
    graph.create_node("probe").subscribe("/joy", "sensor_msgs/Joy", received.append)
    return graph, joy, received


def test_axes_are_ros_ones_and_each_change_goes_out_once() -> None:
    graph, joy, received = _joy({"frame_id": "pad_frame"})
    joy.offer(PAD)
    joy.offer(PAD)  # the same state again: nothing new
    graph.run(duration=1.0)
    assert len(received) == 1
    assert list(received[0].axes) == pytest.approx([0.0, 0.5])
    assert list(received[0].buttons) == [1, 0]
    assert received[0].header.frame_id == "pad_frame"


def test_changes_within_the_coalesce_interval_go_out_as_one() -> None:
    graph, joy, received = _joy({"coalesce_interval": 0.1})
    joy.offer(PAD)  # the first goes at once
    joy.offer(GamepadState("pad", (0.0, -0.3), (1, 0)))
    joy.offer(GamepadState("pad", (0.0, -1.0), (1, 0)))
    graph.run(duration=0.05)
    assert len(received) == 1  # the second and third wait for the interval's end
    graph.run(duration=0.1)
    assert len(received) == 2
    assert received[1].axes[1] == pytest.approx(1.0)  # the newest of them
    first, second = (m.header.stamp for m in received)
    assert (second.sec - first.sec) * 10**9 + second.nanosec - first.nanosec == 100_000_000


def test_an_unchanged_state_repeats_at_the_autorepeat_rate() -> None:
    graph, joy, received = _joy({"autorepeat_rate": 20.0})
    graph.run(duration=0.2)
    assert received == []  # no pad yet: nothing to repeat
    joy.offer(PAD)
    graph.run(duration=1.0)
    assert 19 <= len(received) <= 21
    joy.offer(None)  # the pad went: no more repeats
    graph.run(duration=0.01)
    count = len(received)
    graph.run(duration=0.5)
    assert len(received) == count


def test_the_viewer_topic_is_read_and_bad_states_refused() -> None:
    graph = Graph()
    states: list[Any] = []
    node = graph.create_node("listener")
    node.subscribe(GAMEPAD_TOPIC, GAMEPAD_TYPE, lambda m: states.append(gamepad_from_msg(m)))
    pub = graph.create_node("viewer").publisher(GAMEPAD_TOPIC, GAMEPAD_TYPE)
    pub.publish_data({"header": {"frame_id": "pad"}, "axes": [0.5], "buttons": [1]})
    pub.publish_data({"axes": [float("nan")], "buttons": [1]})
    pub.publish_data({"axes": [0.0], "buttons": [3]})
    pub.publish_data({})
    graph.run(duration=0.1)
    assert states == [
        (True, GamepadState("pad", (0.5,), (1,))),
        (False, None),
        (False, None),
        (True, None),  # no pad
    ]


def test_joy_node_takes_the_viewers_topic_and_keeps_repeating_past_a_bad_message(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    launch = tmp_path / "joy.launch"
    launch.write_text(
        f"""<launch>
          <node pkg="joy" type="joy_node" name="joy_node">
            <param name="port" value="{free_port()}"/>
            <param name="autorepeat_rate" value="10"/>
          </node>
        </launch>"""
    )
    packages = PackageIndex([])
    graph = Graph()
    runtime = LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True)
    runtime.start()
    received: list[Any] = []
    graph.create_node("probe").subscribe("/joy", "sensor_msgs/Joy", received.append)
    pub = graph.create_node("viewer").publisher(GAMEPAD_TOPIC, GAMEPAD_TYPE)
    try:
        graph.run(duration=0.1)
        pub.publish_data({"header": {"frame_id": "pad"}, "axes": [-1.0], "buttons": [1]})
        graph.run(duration=0.05)
        pub.publish_data({"axes": [0.0], "buttons": [7]})
        graph.run(duration=0.9)  # 0.95 s after the state: repeats at 0.1, 0.2, … 0.9 s
    finally:
        runtime.close()
    assert [list(m.axes) for m in received] == [[1.0]] * 10  # the first, then 9 repeats
    assert "/viewer/gamepad: a message that is not a gamepad's state" in caplog.text
