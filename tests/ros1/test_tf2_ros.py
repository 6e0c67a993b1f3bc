"""belvedere's tf2_ros ``Buffer`` against Debian's (``/usr/bin/python3``; tf2's C++ core
through its python binding, no node needed): the same calls on the same transforms give the
same transforms (to 1e-9), the same answers and listings, and the same exception classes
with the same texts."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import pytest
from hypothesis import given, settings

from belvedere.ros1 import message_class, rospy, tf2_ros
from tests.ros1.tf_client import TfOracle, check_steps, oracle_fixture
from tests.ros1.tf_scenarios import run_steps, tf2_scenarios, transform_stamped

pytestmark = pytest.mark.oracle


@pytest.fixture(scope="module")
def oracle() -> Iterator[TfOracle]:
    yield from oracle_fixture()


def ours(scenario: dict[str, Any]) -> list[Any]:
    cache = scenario.get("cache_time")
    buffer = tf2_ros.Buffer(None if cache is None else rospy.Duration(*cache), debug=False)
    return run_steps(buffer, scenario["steps"])


def check(oracle: TfOracle, scenario: dict[str, Any]) -> None:
    check_steps(oracle, "scenarios", scenario, ours)


def ts(parent: str, child: str, secs: float, x: float = 1.0, yaw: float = 0.0) -> dict[str, Any]:
    whole = int(secs)
    stamp = [whole, round((secs - whole) * 1e9)]
    q = [0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)]
    return transform_stamped(parent, child, stamp, [x, 0.5, -0.25], q)


def at(secs: float) -> dict[str, Any]:
    whole = int(secs)
    return {"time": [whole, round((secs - whole) * 1e9)]}


ZERO = {"duration": [0, 0]}
TREE = [
    ["set_transform", ts("map", "odom", 10, 1.0, 0.3), "me"],
    ["set_transform", ts("map", "odom", 12, 3.0, 0.9), "me"],
    ["set_transform", ts("odom", "base", 10.5, 0.5, -0.2), "you"],
    ["set_transform", ts("odom", "base", 11.5, 1.5, 0.4), "you"],
    ["set_transform_static", ts("base", "laser", 0, 0.2, 3.0), "rsp"],
    ["set_transform_static", ts("base", "camera", 5, 0.1, -1.0), "rsp"],
    ["set_transform", ts("world", "other", 10), "me"],
]


@pytest.mark.parametrize(
    "steps",
    [
        pytest.param(
            [
                *TREE,
                ["lookup_transform", "map", "laser", at(11)],
                ["lookup_transform", "laser", "map", at(11.25)],
                ["lookup_transform", "camera", "laser", at(0)],
                ["lookup_transform", "laser", "camera", at(3)],
                ["lookup_transform", "map", "laser", at(0)],
                ["lookup_transform", "map", "base", at(12)],
                ["lookup_transform", "map", "base", at(10.25)],
                ["lookup_transform", "base", "map", at(9)],
                ["lookup_transform", "map", "other", at(0)],
                ["lookup_transform", "map", "nowhere", at(0)],
                ["lookup_transform", "nowhere", "map", at(0)],
                ["lookup_transform", "nowhere", "nowhere", at(0)],
                ["lookup_transform", "base", "base", at(0)],
                ["lookup_transform", "laser", "laser", at(0)],
                ["lookup_transform", "/map", "base", at(0)],
                ["lookup_transform", "map", "", at(0)],
                ["can_transform", "map", "laser", at(0), ZERO, True],
                ["can_transform", "map", "other", at(0), ZERO, True],
                ["can_transform", "map", "base", at(20), ZERO, True],
                ["can_transform", "x", "y", at(0), ZERO, True],
                ["can_transform", "x", "base", at(0), ZERO, True],
                ["can_transform", "/map", "base", at(0), ZERO, True],
                ["can_transform", "map", "base", at(11)],
                ["get_latest_common_time", "map", "laser"],
                ["get_latest_common_time", "base", "laser"],
                ["get_latest_common_time", "map", "other"],
                ["get_latest_common_time", "map", "x"],
                ["lookup_transform_full", "laser", at(10.5), "laser", at(11.5), "map"],
                ["lookup_transform_full", "camera", at(11), "base", at(0), "odom"],
                ["lookup_transform_full", "camera", at(11), "base", at(0), "nowhere"],
                ["can_transform_full", "camera", at(11), "q", at(0), "odom", ZERO, True],
                ["all_frames_as_string"],
                ["all_frames_as_yaml"],
                ["_allFramesAsDot"],
                ["_allFramesAsDot", at(13.5)],
                ["_getFrameStrings"],
                ["_frameExists", "map"],
                ["_frameExists", "nowhere"],
            ],
            id="tree",
        ),
        pytest.param(
            [
                ["set_transform", ts("a", "b", 1), "me"],
                ["set_transform", ts("a", "b", 1, 2.0), "you"],  # repeated stamp: ignored
                ["set_transform", ts("a", "b", 20), "me"],  # the one at 1 s drops out
                ["set_transform", ts("a", "b", 9), "me"],  # older than 10 s before 20: ignored
                ["set_transform", ts("a", "b", 15), "me"],
                ["lookup_transform", "a", "b", at(12)],
                ["lookup_transform", "a", "b", at(1)],
                ["all_frames_as_yaml"],
                ["set_transform", ts("c", "b", 21, 7.0), "me"],  # the parent changes
                ["lookup_transform", "c", "b", at(20.5)],
                ["lookup_transform", "a", "b", at(20.5)],
                ["lookup_transform", "a", "b", at(0)],
                ["lookup_transform", "c", "b", at(0)],
                ["all_frames_as_string"],
                ["clear"],
                ["lookup_transform", "c", "b", at(0)],
                ["can_transform", "c", "b", at(0), ZERO, True],
                ["all_frames_as_string"],
                ["all_frames_as_yaml"],
                ["_allFramesAsDot"],
            ],
            id="history",
        ),
        pytest.param(
            [
                ["set_transform", ts("a", "b", 1), "me"],
                ["set_transform", ts("b", "a", 1), "me"],
                ["lookup_transform", "a", "b", at(1)],
                ["lookup_transform", "a", "b", at(0)],
                ["set_transform", ts("c", "d", 1), "me"],
                ["lookup_transform", "c", "a", at(1)],
                ["lookup_transform", "a", "c", at(0)],
                ["get_latest_common_time", "a", "d"],
                ["can_transform", "a", "c", at(1), ZERO, True],
            ],
            id="loop",
        ),
        pytest.param(
            [
                ["set_transform", ts("a", "a", 1), "me"],
                ["set_transform", ts("", "b", 1), "me"],
                ["set_transform", ts("a", "", 1), "me"],
                ["set_transform", ts("/a", "/b", 1), "me"],
                ["set_transform_static", ts("b", "c", 4), "me"],
                ["set_transform", ts("b", "c", 6), "me"],  # a static frame replaced
                ["lookup_transform", "a", "c", at(1)],
                ["lookup_transform", "a", "c", at(0)],
                ["set_transform", ts("c", "d", 0), "me"],
                ["set_transform_static", ts("c", "d", 1), "me"],  # a dynamic frame stays so
                ["lookup_transform", "c", "d", at(0)],
                ["lookup_transform", "c", "d", at(3)],
                ["all_frames_as_yaml"],
            ],
            id="inputs",
        ),
        pytest.param(
            [
                ["all_frames_as_string"],
                ["all_frames_as_yaml"],
                ["_allFramesAsDot"],
                ["_getFrameStrings"],
                ["lookup_transform", "a", "b", at(0)],
                ["can_transform", "a", "b", at(0), ZERO, True],
            ],
            id="empty",
        ),
    ],
)
def test_scenario(oracle: TfOracle, steps: list[Any]) -> None:
    check(oracle, {"cache_time": None, "steps": steps})


@settings(max_examples=400)
@given(tf2_scenarios())
def test_generated_scenarios(oracle: TfOracle, scenario: dict[str, Any]) -> None:
    check(oracle, scenario)


def test_exceptions_are_tf2s() -> None:
    assert issubclass(tf2_ros.LookupException, tf2_ros.TransformException)
    assert tf2_ros.LookupException.__module__ == "tf2"  # as tracebacks name it
    buffer = tf2_ros.Buffer(debug=False)
    with pytest.raises(tf2_ros.LookupException) as caught:
        buffer.lookup_transform("a", "b", rospy.Time(0))
    text = '"a" passed to lookupTransform argument target_frame does not exist. '
    assert str(caught.value) == text


def test_time_must_be_a_time() -> None:
    buffer = tf2_ros.Buffer(debug=False)
    with pytest.raises(TypeError, match="time must have a to_sec method"):
        buffer.lookup_transform("a", "b", 0)
    with pytest.raises(TypeError, match="time must have a to_sec method"):
        tf2_ros.Buffer(5.0)


def test_transform_needs_a_registered_type() -> None:
    buffer = tf2_ros.Buffer(debug=False)
    twist = message_class("geometry_msgs/TwistStamped")()  # tf2_geometry_msgs has no twists
    with pytest.raises(tf2_ros.TypeException, match="if not loaded or supported"):
        buffer.transform(twist, "a")
