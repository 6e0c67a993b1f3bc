"""Messages from rostopic-style YAML and back to rostopic echo text."""

from __future__ import annotations

import contextlib
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from belvedere.msgs import (
    MessageTypeError,
    MessageValueError,
    message_from_args,
    message_from_data,
    message_to_data,
    message_to_yaml,
    types,
)

SEED = "{linear: {x: 0.2, y: 0, z: 0}, angular: {x: 0, y: 0, z: 0.5}}"


def test_seed_command_yaml() -> None:
    msg = message_from_args("geometry_msgs/Twist", [SEED])
    assert (msg.linear.x, msg.angular.z) == (0.2, 0.5)
    assert message_to_yaml(msg) == (
        "linear: \n  x: 0.2\n  y: 0.0\n  z: 0.0\nangular: \n  x: 0.0\n  y: 0.0\n  z: 0.5"
    )


def test_a_message_without_fields_shows_nothing() -> None:
    """rosbags gives such types a placeholder member (ROS 2 needs one); ROS 1 has none, and
    rosservice prints an empty response as nothing."""
    for type_name in ("std_msgs/Empty", "std_srvs/srv/Empty_Response"):
        msg = message_from_data(type_name, None)
        assert message_to_yaml(msg) == ""
        assert message_to_data(msg) == {}
        assert message_from_data(type_name, message_to_data(msg)) == msg


def test_both_type_spellings() -> None:
    a = message_from_args("geometry_msgs/Twist", [SEED])
    b = message_from_args("geometry_msgs/msg/Twist", [SEED])
    assert message_to_data(a) == message_to_data(b)


def test_positional_arguments() -> None:
    msg = message_from_args("geometry_msgs/Twist", ["[0.2, 0, 0]", "[0, 0, 0.5]"])
    assert (msg.linear.x, msg.angular.z) == (0.2, 0.5)
    assert message_from_args("std_msgs/String", ["hi"]).data == "hi"


def test_partial_and_default() -> None:
    msg = message_from_args("geometry_msgs/Twist", ["{angular: {z: 1}}"])
    assert (msg.linear.x, msg.angular.z) == (0.0, 1.0)
    assert message_to_data(message_from_args("geometry_msgs/Twist", ["{}"]))["linear"] == {
        "x": 0.0,
        "y": 0.0,
        "z": 0.0,
    }


def test_header_auto_and_now() -> None:
    clock = lambda: (12, 345)  # noqa: E731
    msg = message_from_args("geometry_msgs/PoseStamped", ["{header: auto}"], clock=clock, seq=7)
    assert (msg.header.seq, msg.header.stamp.sec, msg.header.stamp.nanosec) == (7, 12, 345)
    stamped = message_from_data("std_msgs/Header", {"stamp": "now"}, clock=clock)
    assert stamped.stamp.sec == 12
    seconds = message_from_data("std_msgs/Header", {"stamp": 1.5})
    assert (seconds.stamp.sec, seconds.stamp.nanosec) == (1, 500_000_000)
    ros1 = message_from_data("std_msgs/Header", {"stamp": {"secs": 3, "nsecs": 4}})
    assert (ros1.stamp.sec, ros1.stamp.nanosec) == (3, 4)


@pytest.mark.parametrize(
    ("type_name", "args", "error"),
    [
        ("std_msgs/String", ["data: 1"], "field 'data': expected a string, got 1"),
        ("geometry_msgs/Twist", ["{linear: {w: 1}}"], "field 'linear.w' does not exist"),
        ("geometry_msgs/Twist", ["{linear: {x: abc}}"], "field 'linear.x': expected float64"),
        ("std_msgs/UInt8", ["data: 300"], "field 'data': 300 does not fit uint8 (0 to 255)"),
        ("std_msgs/Bool", ["data: 2"], "expected a bool"),
        ("geometry_msgs/Twist", ["[1, 2, 3]", "[1]", "[2]"], "at most 2 values"),
        ("std_msgs/Float64MultiArray", ["{data: 5}"], "field 'data': expected a list"),
        ("geometry_msgs/PoseWithCovariance", ["{covariance: [1, 2]}"], "exactly 36 values"),
        ("std_msgs/String", ["{data: [unclosed"], "is not valid YAML"),
    ],
)
def test_errors_name_the_field(type_name: str, args: list[str], error: str) -> None:
    with pytest.raises(MessageValueError) as info:
        message_from_args(type_name, args)
    assert error in str(info.value)


def test_unknown_type_suggests() -> None:
    with pytest.raises(MessageTypeError, match="unknown message type 'geometry_msgs/Twst'") as info:
        message_from_args("geometry_msgs/Twst", ["{}"])
    assert "geometry_msgs/Twist" in str(info.value)
    with pytest.raises(MessageTypeError, match="malformed type name"):
        types().resolve("Twist")


def test_echo_arrays_strings_and_noarr() -> None:
    scan = message_from_data(
        "sensor_msgs/LaserScan", {"ranges": [1.0, 2.5], "header": {"frame_id": "laser"}}
    )
    text = message_to_yaml(scan)
    assert 'frame_id: "laser"' in text
    assert "ranges: [1.0, 2.5]" in text
    assert 'ranges: "<array type: float32, length: 2>"' in message_to_yaml(scan, noarr=True)
    tf = message_from_data("tf2_msgs/TFMessage", {"transforms": [{"child_frame_id": "a"}]})
    assert "transforms: \n  - \n    header: \n" in message_to_yaml(tf)


def test_extra_standard_types_exist() -> None:
    for name in (
        "tf2_msgs/TFMessage",
        "control_msgs/FollowJointTrajectoryActionGoal",
        "rosgraph_msgs/Clock",
        "nav_msgs/OccupancyGrid",
        "sensor_msgs/JointState",
    ):
        types().resolve(name)
    assert types().resolve_service("std_srvs/Trigger") == "std_srvs/srv/Trigger"


def test_cdr_round_trip() -> None:
    msg = message_from_data("sensor_msgs/JointState", {"name": ["a", "b"], "position": [1.0, -2.0]})
    back = types().deserialize(types().serialize(msg), "sensor_msgs/JointState")
    assert back.name == ["a", "b"]
    assert np.array_equal(back.position, [1.0, -2.0])


# --- fuzzing: any YAML-shaped input gives a message or a clear error --------------------------

yaml_values: st.SearchStrategy[Any] = st.recursive(
    st.none()
    | st.booleans()
    | st.integers(-(2**70), 2**70)
    | st.floats(allow_nan=True)
    | st.text(max_size=8),
    lambda inner: (
        st.lists(inner, max_size=4)
        | st.dictionaries(
            st.sampled_from(["x", "y", "z", "data", "header", "linear", "stamp", "name", "w"]),
            inner,
            max_size=4,
        )
    ),
    max_leaves=12,
)
TYPES = [
    "geometry_msgs/Twist",
    "geometry_msgs/PoseStamped",
    "sensor_msgs/JointState",
    "std_msgs/String",
    "std_msgs/UInt8MultiArray",
    "nav_msgs/Odometry",
    "sensor_msgs/LaserScan",
]


@settings(max_examples=400, deadline=None)
@given(st.sampled_from(TYPES), yaml_values)
def test_fuzz_only_clear_errors(type_name: str, data: Any) -> None:
    try:
        msg = message_from_data(type_name, data, clock=lambda: (1, 2))
    except MessageValueError as err:
        text = str(err)
        clear = any(
            words in text for words in ("expected", "does not exist", "needs a clock", "not fit")
        )
        assert clear, text
        return
    types().serialize(msg)  # a message we build always serializes
    message_to_yaml(msg)


@settings(max_examples=200, deadline=None)
@given(st.sampled_from(TYPES), st.text(max_size=30))
def test_fuzz_command_line_text(type_name: str, text: str) -> None:
    with contextlib.suppress(MessageValueError):
        message_from_args(type_name, [text])


BIG = "9" * 321


@pytest.mark.parametrize(
    ("type_name", "args", "error"),
    [
        (
            "std_msgs/Float32",
            [BIG],
            "field 'data': a 321-digit integer does not fit float32 (±3.4028235e+38)",
        ),
        (
            "std_msgs/Float32",
            ["1.0e+300"],
            "field 'data': 1e+300 does not fit float32 (±3.4028235e+38)",
        ),
        (
            "std_msgs/Float64",
            [BIG],
            "field 'data': a 321-digit integer does not fit float64 (±1.7976931348623157e+308)",
        ),
        (
            "std_msgs/Time",
            [BIG],
            "field 'data': a 321-digit integer does not fit a time "
            "(0 to 2147483647 s: int32 seconds on the wire)",
        ),
        (
            "std_msgs/Time",
            ["{data: {secs: 0, nsecs: -1}}"],
            "field 'data': {'secs': 0, 'nsecs': -1} does not fit a time (0 to 2147483647 s",
        ),
        (
            "std_msgs/Duration",
            ["{data: {secs: 2147483647, nsecs: 1000000000}}"],
            "does not fit a duration (-2147483648 to 2147483647 s",
        ),
        (
            "sensor_msgs/LaserScan",
            ["{ranges: [1, 2, 1.0e+39]}"],
            "field 'ranges[2]': 1e+39 does not fit float32 (±3.4028235e+38)",
        ),
        (
            "std_msgs/Int64",
            [BIG],
            "field 'data': a 321-digit integer does not fit int64 "
            "(-9223372036854775808 to 9223372036854775807)",
        ),
        (
            "std_msgs/String",
            ["a: " + "9" * 5000],
            "is not valid YAML at column 4: Exceeds the limit (4300 digits)",
        ),
        (
            "std_msgs/String",
            ["[" * 200 + "]" * 200],
            "is not valid YAML at column 129: collections nest more than 128 levels deep",
        ),
        (
            "std_msgs/String",
            ["&a [*a]"],
            "is not valid YAML at column 1: a YAML alias refers to the value that contains it",
        ),
        (
            "trajectory_msgs/JointTrajectory",
            [
                "{a: &a [0, 0, 0, 0, 0, 0, 0, 0, 0, 0], b: &b [*a, *a, *a, *a, *a, *a, *a, *a], "
                "c: &c [*b, *b, *b, *b, *b, *b, *b, *b], d: &d [*c, *c, *c, *c, *c, *c, *c, *c],"
                " e: &e [*d, *d, *d, *d, *d, *d, *d, *d], f: &f [*e, *e, *e, *e, *e, *e, *e, *e],"
                " g: [*f, *f, *f, *f, *f, *f, *f, *f]}"
            ],
            "YAML aliases here expand to more than 1,000,000 values (an alias bomb?)",
        ),
    ],
)
def test_values_that_do_not_fit_their_field(type_name: str, args: list[str], error: str) -> None:
    with pytest.raises(MessageValueError) as info:
        message_from_args(type_name, args)
    assert error in str(info.value)


def test_extreme_values_that_fit_are_kept_and_serialize() -> None:
    scan = message_from_args(
        "sensor_msgs/LaserScan", ["{ranges: [.inf, -.inf, .nan, 3.4028235e+38, 1.0e-50]}"]
    )
    back = types().deserialize(types().serialize(scan), "sensor_msgs/LaserScan")
    assert np.isinf(back.ranges[:2]).all()
    assert np.isnan(back.ranges[2])
    assert back.ranges[3] == np.finfo(np.float32).max
    # Durations and times carry nanoseconds as rospy does: 1 s - 1 ns is 0 s + 999999999 ns.
    duration = message_from_args("std_msgs/Duration", ["{data: {secs: 1, nsecs: -1}}"])
    assert (duration.data.sec, duration.data.nanosec) == (0, 999_999_999)
    later = message_from_args("std_msgs/Time", ["{data: {secs: 1, nsecs: 2500000000}}"])
    assert (later.data.sec, later.data.nanosec) == (3, 500_000_000)
    negative = message_from_args("std_msgs/Duration", ["{data: -1.25}"])
    assert (negative.data.sec, negative.data.nanosec) == (-2, 750_000_000)
    for msg, name in ((duration, "std_msgs/Duration"), (later, "std_msgs/Time")):
        types().deserialize(types().serialize(msg), name)


@pytest.mark.parametrize("stamp", [2147483648.0, -2147483649, {"secs": 0, "nsecs": -1}])
def test_a_time_beyond_int32_seconds_is_a_clear_error(stamp: Any) -> None:
    with pytest.raises(
        MessageValueError,
        match=r"field 'header\.stamp': .* does not fit a time \(0 to 2147483647 s",
    ):
        message_from_data("geometry_msgs/PoseStamped", {"header": {"stamp": stamp}})


def test_a_time_just_below_a_whole_second_carries() -> None:
    msg = message_from_data("std_msgs/Header", {"stamp": 1.9999999999})
    assert (msg.stamp.sec, msg.stamp.nanosec) == (2, 0)


def test_byte_is_ros1s_signed_8_bit_integer() -> None:
    """ROS 1's ``byte`` is int8 (genpy packs it as 'b'): -1 fits and is sent as 0xff; 200 is
    one clear error at the publisher, not a struct error when serializing."""
    msg = message_from_args("std_msgs/Byte", ["-1"])
    assert types().serialize(msg)[-1:] == b"\xff"
    with pytest.raises(MessageValueError, match=r"200 does not fit byte \(-128 to 127\)"):
        message_from_args("std_msgs/Byte", ["200"])
    raw = message_from_data("std_msgs/ByteMultiArray", {"data": b"\x01\xff"})
    assert raw.data.tolist() == [1, -1]
