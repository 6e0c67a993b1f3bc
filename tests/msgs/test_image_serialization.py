"""Messages ending in a large byte array (Image) are serialized by joining the pixels on:
the same CDR bytes as rosbags writes, and they read back."""

from __future__ import annotations

import numpy as np
import pytest

from belvedere.msgs import build, types


@pytest.mark.parametrize("frame", ["", "c", "camera_link", "abc"])
@pytest.mark.parametrize("encoding", ["rgb8", "mono16"])
def test_image_bytes_equal_rosbags(frame: str, encoding: str) -> None:
    registry = types()
    data = np.random.default_rng(0).integers(0, 255, 64 * 48 * 3, dtype=np.uint8)
    image = registry.cls("sensor_msgs/Image")(
        build.header(1_234_567_891, frame), 48, 64, encoding, 0, 192, data
    )
    fast = registry.serialize(image)
    assert fast == bytes(registry.store.serialize_cdr(image, image.__msgtype__))
    back = registry.deserialize(fast, "sensor_msgs/Image")
    assert (back.header.frame_id, back.encoding, back.width) == (frame, encoding, 64)
    assert np.array_equal(back.data, data)
