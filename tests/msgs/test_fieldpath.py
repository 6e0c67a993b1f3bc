"""rqt_plot's field paths: split as its command line takes them, resolved against the
graph's topics, and the numbers read from real messages."""

from __future__ import annotations

import math
import re

import pytest

from belvedere.msgs import (
    FieldPathError,
    field_value,
    message_from_data,
    resolve_series,
    split_plot_args,
)

TOPICS = {
    "/odom": "nav_msgs/Odometry",
    "/turtle1/pose": "turtlesim/Pose",
    "/joint_states": "sensor_msgs/JointState",
    "/rosout": "rosgraph_msgs/Log",
}


def test_arguments_split_on_spaces_commas_and_colons() -> None:
    words = ["/turtle1/pose/x:y", "/odom/pose/pose/position/x,joint_states/position[0]"]
    assert split_plot_args(words) == [
        "/turtle1/pose/x",
        "/turtle1/pose/y",
        "/odom/pose/pose/position/x",
        "/joint_states/position[0]",
    ]


def test_the_longest_topic_is_the_topic_and_the_rest_the_field() -> None:
    topics = {**TOPICS, "/odom/pose": "std_msgs/Float64"}
    (series,) = resolve_series("/odom/pose/data", topics) or []
    assert (series.topic, series.steps) == ("/odom/pose", (("data", None),))
    (series,) = resolve_series("/odom/pose/pose/position/x", TOPICS) or []
    assert series.topic == "/odom"
    assert series.label == "/odom/pose/pose/position/x"


def test_a_message_path_stands_for_its_numeric_fields() -> None:
    found = resolve_series("/turtle1/pose", TOPICS) or []
    assert [s.label for s in found] == [
        "/turtle1/pose/x",
        "/turtle1/pose/y",
        "/turtle1/pose/theta",
        "/turtle1/pose/linear_velocity",
        "/turtle1/pose/angular_velocity",
    ]


def test_an_unpublished_topic_waits() -> None:
    assert resolve_series("/cmd_vel/linear/x", TOPICS) is None


@pytest.mark.parametrize(
    ("path", "expected"),
    [
        ("/odom/pose/pose/position/w", "no field 'w' (fields here: x, y, z)"),
        ("/joint_states/position", "'position' is an array: name an element, as position[0]"),
        ("/odom/pose/pose/position/x[2]", "'x' is not an array"),
        ("/rosout/name", "not a number (a str)"),
        ("/odom/pose/pose/position/x-y", "'x-y' is no field name"),
    ],
)
def test_a_path_to_no_number_is_one_clear_error(path: str, expected: str) -> None:
    with pytest.raises(FieldPathError, match=re.escape(expected)):
        resolve_series(path, TOPICS)


def test_values_are_read_from_real_messages() -> None:
    (x,) = resolve_series("/odom/pose/pose/position/x", TOPICS) or []
    odom = message_from_data("nav_msgs/Odometry", {"pose": {"pose": {"position": {"x": 1.5}}}})
    assert field_value(odom, x.steps) == 1.5
    (second,) = resolve_series("/joint_states/position[1]", TOPICS) or []
    joints = message_from_data("sensor_msgs/JointState", {"name": ["a", "b"], "position": [3, 4]})
    assert field_value(joints, second.steps) == 4.0
    short = message_from_data("sensor_msgs/JointState", {"name": ["a"], "position": [3]})
    assert field_value(short, second.steps) is None  # a gap, as rqt_plot leaves
    nan = message_from_data("sensor_msgs/JointState", {"position": [0.0, math.nan]})
    assert field_value(nan, second.steps) is None
