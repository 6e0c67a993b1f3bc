"""rqt_plot's field paths against Debian's ROS: the number belvedere reads at a path is the one
``rostopic.msgevalgen`` (the evaluator rostopic echo and rqt_plot's path parsing share) reads
from genpy's message filled with the same values."""

from __future__ import annotations

import json
import subprocess

import pytest

from belvedere.msgs import field_value, message_from_data, resolve_series
from tests.debian_ros import ROS_PYTHON, missing_debian_ros

CASES = [
    ("geometry_msgs/PoseStamped", {"pose": {"position": {"x": 1.25, "z": -3}}}, "/pose/position/x"),
    ("geometry_msgs/PoseStamped", {"pose": {"orientation": {"w": 1}}}, "/pose/orientation/w"),
    ("sensor_msgs/JointState", {"name": ["a", "b"], "position": [3, 4.5]}, "/position[1]"),
    ("sensor_msgs/JointState", {"name": ["a"], "position": [3]}, "/position[4]"),
    (
        "geometry_msgs/PoseWithCovariance",
        {"covariance": [float(i) for i in range(36)]},
        "/covariance[7]",
    ),
    ("sensor_msgs/Imu", {"angular_velocity": {"z": 0.5}}, "/angular_velocity/z"),
    ("std_msgs/Float64MultiArray", {"data": [1.0, 2.0, 3.0]}, "/data[2]"),
    ("std_msgs/Float64MultiArray", {"layout": {"data_offset": 7}}, "/layout/data_offset"),
    ("sensor_msgs/Range", {"range": 2.5, "radiation_type": 1}, "/radiation_type"),
]

ORACLE = """
import json, sys
import genpy.message, roslib.message, rostopic
out = []
for type_name, data, path in json.loads(sys.stdin.read()):
    msg = roslib.message.get_message_class(type_name)()
    genpy.message.fill_message_args(msg, [data])
    value = rostopic.msgevalgen(path)(msg)
    out.append(None if value is None else float(value))
print(json.dumps(out))
"""


def test_values_at_paths_match_rostopics() -> None:
    reason = missing_debian_ros("rostopic, genpy, geometry_msgs.msg, sensor_msgs.msg")
    if reason:
        pytest.skip(reason)
    done = subprocess.run(
        [str(ROS_PYTHON), "-c", ORACLE],
        input=json.dumps(CASES),
        capture_output=True,
        text=True,
        timeout=60,
        check=True,
    )
    theirs = json.loads(done.stdout.splitlines()[-1])
    ours = []
    for type_name, data, path in CASES:
        (series,) = resolve_series("/t" + path, {"/t": type_name}) or []
        ours.append(field_value(message_from_data(type_name, data), series.steps))
    assert ours == theirs
