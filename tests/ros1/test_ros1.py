"""belvedere.ros1 on its own: round trips (hypothesis), the import hook, time values."""

from __future__ import annotations

import importlib
import sys
from functools import cache, partial
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

import belvedere.ros1 as ros1
from belvedere.ros1 import Duration, Time, from_store, message_class, serialize_message, to_store
from belvedere.ros1._spec import FieldSpec, message_spec
from tests.ros1.filling import INT_RANGES

ROUND_TRIP_TYPES = [
    "sensor_msgs/msg/JointState",
    "sensor_msgs/msg/CameraInfo",
    "sensor_msgs/msg/Image",
    "nav_msgs/msg/Odometry",
    "tf2_msgs/msg/TFMessage",
    "visualization_msgs/msg/Marker",
    "trajectory_msgs/msg/JointTrajectory",
    "diagnostic_msgs/msg/DiagnosticArray",
]


def _field(field: FieldSpec) -> st.SearchStrategy[Any]:
    single = _single(field)
    if field.array is None:
        return single
    if field.base in ("uint8", "char"):
        size = field.array
        return st.binary(min_size=size, max_size=size) if size else st.binary(max_size=8)
    if field.array:
        return st.lists(single, min_size=field.array, max_size=field.array)
    return st.lists(single, max_size=3)


def _single(field: FieldSpec) -> st.SearchStrategy[Any]:
    base = field.base
    if field.is_message:
        return messages(base)
    if base == "time":
        # up to 2**31: the store keeps time's seconds as int32 (ROS 1's are uint32)
        return st.builds(Time, st.integers(0, 2**31 - 1), st.integers(0, 10**9 - 1))
    if base == "duration":
        return st.builds(Duration, st.integers(-(2**31), 2**31 - 1), st.integers(0, 10**9 - 1))
    if base in INT_RANGES:
        return st.integers(*INT_RANGES[base])
    if base == "float64":
        return st.floats(allow_nan=False)
    if base == "float32":
        return st.floats(width=32, allow_nan=False)
    if base == "bool":
        return st.booleans()
    assert base == "string"
    return st.text(st.characters(exclude_categories=["Cs"]), max_size=6)


@cache
def messages(name: str) -> st.SearchStrategy[ros1.Message]:
    spec = message_spec(name)
    cls = message_class(name)
    fields = st.fixed_dictionaries({f.name: _field(f) for f in spec.fields})
    return fields.map(partial(_construct, cls))


def _construct(cls: type[ros1.Message], values: dict[str, Any]) -> ros1.Message:
    return cls(**values)


@pytest.mark.parametrize("name", ROUND_TRIP_TYPES)
@given(data=st.data())
def test_wire_and_store_round_trips(name: str, data: st.DataObject) -> None:
    msg = data.draw(messages(name))
    wire = serialize_message(msg)
    back = message_class(name)().deserialize(wire)
    assert back == msg
    assert serialize_message(back) == wire
    assert from_store(to_store(msg)) == msg


def test_import_hook_is_opt_in() -> None:
    import belvedere  # noqa: F401

    assert ros1.installed() is None
    assert not any(isinstance(f, ros1.RosModuleFinder) for f in sys.meta_path)


def test_import_hook_provides_msg_and_srv_modules() -> None:
    ros1.install()
    try:
        assert ros1.install() is ros1.installed()  # once only
        assert sys.meta_path[-1] is ros1.installed()  # after any real ROS
        msg_module = importlib.import_module("gazebo_msgs.msg")
        srv_module = importlib.import_module("gazebo_msgs.srv")
        assert msg_module.ModelState is message_class("gazebo_msgs/ModelState")
        service = srv_module.SpawnModel
        assert service._type == "gazebo_msgs/SpawnModel"
        assert srv_module.SpawnModelRequest is service._request_class
        assert srv_module.SpawnModelResponse is service._response_class
        assert "ModelStates" in dir(msg_module)
        with pytest.raises(AttributeError, match="Nope"):
            _ = msg_module.Nope
    finally:
        ros1.uninstall()
    assert "gazebo_msgs.msg" not in sys.modules
    assert ros1.installed() is None


def test_constants_and_defaults() -> None:
    marker: Any = message_class("visualization_msgs/Marker")
    assert marker.DELETEALL == 3
    camera: Any = message_class("sensor_msgs/CameraInfo")()
    assert camera.K == [0.0] * 9
    assert camera.D == []
    assert isinstance(camera.header.stamp, Time)
    image: Any = message_class("sensor_msgs/Image")()
    assert image.data == b""
    a: Any = message_class("nav_msgs/Path")()
    b: Any = message_class("nav_msgs/Path")()
    a.poses.append(1)
    assert b.poses == []  # defaults are not shared


def test_time_and_duration() -> None:
    t = Time(5, 1_500_000_000)
    assert (t.secs, t.nsecs) == (6, 500_000_000)
    assert repr(t) == "genpy.Time[6500000000]"
    assert str(Duration(-1, 5)) == "-999999995"
    assert t + Duration(1) == Time(7, 500_000_000)
    assert t - Time(6) == Duration(0, 500_000_000)
    assert Duration.from_sec(1.5) * 2 == Duration(3)
    assert Duration(3) / Duration(2) == 1.5
    assert Time(1) < Time(2)
    assert Time(1) != Duration(1)
    assert Time.from_sec(2.25).to_nsec() == 2_250_000_000
    assert Time().is_zero()
    with pytest.raises(TypeError, match="time values must be positive"):
        Time(-1)
    with pytest.raises(TypeError):
        _ = Time(1) < Duration(1)


# move_base_msgs' sums as ROS publishes them (rosserial's generated headers carry the same).
MOVE_BASE_MD5 = {
    "MoveBaseAction": "70b6aca7c7f7746d8d1609ad94c80bb8",
    "MoveBaseActionGoal": "660d6895a1b9a16dce51fbdd9a64a56b",
    "MoveBaseActionResult": "1eb06eeff08fa7ea874431638cb52332",
    "MoveBaseActionFeedback": "7d1870ff6e0decea702b943b5af0b42e",
    "MoveBaseGoal": "257d089627d7eb7136c24d3593d05a16",
    "MoveBaseResult": "d41d8cd98f00b204e9800998ecf8427e",
    "MoveBaseFeedback": "3fb824c456a757373a226f6d08071bf0",
}


def test_move_base_action_types() -> None:
    for name, md5 in MOVE_BASE_MD5.items():
        assert message_class(f"move_base_msgs/{name}")._md5sum == md5, name
    # actionlib finds an action's three wire types from an instance of the *Action class
    action: Any = message_class("move_base_msgs/MoveBaseAction")()
    assert type(action.action_goal) is message_class("move_base_msgs/MoveBaseActionGoal")
    assert type(action.action_result.result) is message_class("move_base_msgs/MoveBaseResult")
    assert type(action.action_feedback.feedback.base_position).__name__ == "PoseStamped"
