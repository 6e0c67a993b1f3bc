"""A message's ROS 1 bytes in parts (its large last string or byte array apart, encoded
once): joined, exactly rosbags' bytes, which read back to the message; other messages are
one part, as rosbags writes them. A connection's reader of ROS 1 bytes reads as rosbags
does."""

from __future__ import annotations

import struct
from dataclasses import replace
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from rosbags.serde import SerdeError

from belvedere.msgs import build, message_from_data, types
from belvedere.msgs._ros1bytes import BULK_BYTES, holds_views


def _joined(msg: Any) -> tuple[int, bytes]:
    parts = types().ros1_parts(msg, msg.__msgtype__)
    return len(parts), b"".join(bytes(p) for p in parts)


def _rosbags(msg: Any) -> bytes:
    return bytes(types().store.serialize_ros1(msg, msg.__msgtype__))


@settings(max_examples=40, deadline=None)
@given(
    text=st.text(min_size=0, max_size=300),
    repeat=st.sampled_from([1, 20, 200]),
)
def test_a_string_message_is_rosbags_bytes_small_or_large(text: str, repeat: int) -> None:
    msg = types().cls("std_msgs/String")(data=text * repeat)
    count, data = _joined(msg)
    assert data == _rosbags(msg)
    assert types().store.deserialize_ros1(data, msg.__msgtype__) == msg
    assert count == (2 if len(msg.data) > BULK_BYTES else 1)


def test_a_megabyte_string_is_sent_as_its_head_and_its_text_encoded_once() -> None:
    text = "1732790000.123456|" + "é" * (1 << 19)
    msg = types().cls("std_msgs/String")(data=text)
    head, bulk = types().ros1_parts(msg, msg.__msgtype__)
    assert bytes(head) == len(text.encode()).to_bytes(4, "little")
    assert bytes(bulk) == text.encode()


def test_an_image_and_a_compressed_image_are_rosbags_bytes_with_their_pixels_apart() -> None:
    rng = np.random.default_rng(3)
    pixels = rng.integers(0, 255, 480 * 640 * 3, dtype=np.uint8)
    image = types().cls("sensor_msgs/Image")(
        build.header(1_234_567_891, "camera", seq=7), 480, 640, "rgb8", 0, 1920, pixels
    )
    compressed = types().cls("sensor_msgs/CompressedImage")(
        build.header(5, "camera"), "jpeg", pixels[:50_000]
    )
    for msg in (image, compressed):
        count, data = _joined(msg)
        assert (count, data) == (2, _rosbags(msg))
        back: Any = types().store.deserialize_ros1(data, msg.__msgtype__)
        assert np.array_equal(back.data, msg.data)
        assert back.header == msg.header


def test_a_strided_byte_array_is_sent_as_its_values() -> None:
    pixels = np.arange(20_000, dtype=np.uint8)[::2]  # a view that is not contiguous
    msg = types().cls("sensor_msgs/CompressedImage")(build.header(5, "c"), "png", pixels)
    assert _joined(msg) == (2, _rosbags(msg))


def test_messages_without_a_large_tail_are_one_part() -> None:
    cloud = message_from_data("sensor_msgs/PointCloud2", {"height": 1, "width": 2})
    cloud = replace(cloud, data=np.arange(10_000, dtype=np.uint8))  # data is not its last
    small_image = types().cls("sensor_msgs/Image")(
        build.header(1, "c"), 2, 2, "mono8", 0, 2, np.arange(4, dtype=np.uint8)
    )
    small_jpeg = types().cls("sensor_msgs/CompressedImage")(
        build.header(1, "c"), "jpeg", np.arange(BULK_BYTES, dtype=np.uint8)
    )
    twist = message_from_data("geometry_msgs/Twist", {"linear": {"x": 0.5}})
    for msg in (cloud, small_image, small_jpeg, twist):
        assert _joined(msg) == (1, _rosbags(msg))


def test_the_ros1_reader_reads_what_rosbags_reads_and_refuses_what_it_refuses() -> None:
    registry = types()
    image = registry.cls("sensor_msgs/Image")(
        build.header(9, "cam", seq=3), 2, 3, "rgb8", 1, 9, np.arange(18, dtype=np.uint8)
    )
    data = _rosbags(image)
    read = registry.ros1_reader(image.__msgtype__)
    back = read(data)
    assert back.header == image.header
    assert np.array_equal(back.data, image.data)
    assert read(memoryview(data)).encoding == "rgb8"
    with pytest.raises(SerdeError, match="bytes for a sensor_msgs/Image of"):
        read(data + b"\x00")
    with pytest.raises((SerdeError, struct.error)):
        read(data[:-5])
    with pytest.raises(UnicodeDecodeError):
        registry.ros1_reader("std_msgs/msg/String")(b"\x02\x00\x00\x00\xff\xfe")


def test_which_types_hold_views_of_the_bytes_they_are_read_from() -> None:
    store = types().store
    holding = {
        name: holds_views(store, name)
        for name in (
            "std_msgs/msg/String",
            "std_msgs/msg/Header",
            "geometry_msgs/msg/Twist",
            "geometry_msgs/msg/PoseArray",
            "diagnostic_msgs/msg/DiagnosticArray",
            "sensor_msgs/msg/Image",
            "sensor_msgs/msg/LaserScan",
            "sensor_msgs/msg/JointState",
            "geometry_msgs/msg/PoseWithCovarianceStamped",
            "nav_msgs/msg/Path",
        )
    }
    assert [name for name, views in holding.items() if views] == [
        "sensor_msgs/msg/Image",
        "sensor_msgs/msg/LaserScan",
        "sensor_msgs/msg/JointState",
        "geometry_msgs/msg/PoseWithCovarianceStamped",
    ]


def test_a_borrowed_buffer_overwritten_after_reading_leaves_the_messages_as_read() -> None:
    registry = types()
    scan = message_from_data("sensor_msgs/LaserScan", {"ranges": [1.5, 2.5, 3.5]})
    text = registry.cls("std_msgs/String")(data="ünïcode")
    for msg in (scan, text):
        buffer = bytearray(_rosbags(msg))
        back = registry.ros1_reader(msg.__msgtype__, borrowed=True)(memoryview(buffer))
        buffer[:] = bytes(len(buffer))
        if msg is scan:
            assert back.ranges.tolist() == [1.5, 2.5, 3.5]
        else:
            assert back == text
