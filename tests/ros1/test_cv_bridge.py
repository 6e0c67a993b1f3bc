"""cv_bridge against Debian's python3-cv-bridge on generated images: every encoding to every
encoding (bytes, shape and dtype of the image, or the error's type and text), numpy images
to messages (encoding, step, is_bigendian, bytes), and JPEG/PNG round trips."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from belvedere.ros1 import message_class
from belvedere.ros1.cv_bridge import CvBridge, CvBridgeError
from tests.debian_ros import ROS_PYTHON, missing_debian_ros
from tests.ros1.cv_bridge_oracle import answer

ORACLE = Path(__file__).with_name("cv_bridge_oracle.py")

ENCODINGS = (
    "rgb8", "bgr8", "rgba8", "bgra8", "mono8", "mono16", "rgb16", "bgr16", "rgba16",
    "bgra16", "bayer_rggb8", "bayer_bggr8", "bayer_gbrg8", "bayer_grbg8", "bayer_rggb16",
    "8UC1", "8UC3", "8UC4", "8SC1", "16UC1", "16SC1", "16UC3", "32SC1", "32FC1", "32FC2",
    "32FC3", "32FC4", "64FC1", "8UC2", "yuv422",
)  # fmt: skip
DESIRED = ("passthrough", "rgb8", "bgr8", "mono8", "mono16", "bgra8", "rgba16", "32FC1", "8UC3")
DTYPES = {"8U": "u1", "8S": "i1", "16U": "u2", "16S": "i2", "32S": "i4", "32F": "f4", "64F": "f8"}


def _pixels(encoding: str, height: int, width: int, bigendian: bool) -> tuple[bytes, int]:
    bridge = CvBridge()
    name, count = bridge.encoding_to_dtype_with_channels(encoding)
    rng = np.random.default_rng(sum(map(ord, encoding)) + height)
    dtype = np.dtype(name).newbyteorder(">" if bigendian else "<")
    if dtype.kind == "f":
        values = rng.uniform(0.0, 8.0, size=height * width * count).astype(dtype)
    else:
        info = np.iinfo(dtype)
        values = rng.integers(info.min, info.max, size=height * width * count, endpoint=True)
        values = values.astype(dtype)
    return values.tobytes(), width * count * dtype.itemsize


def _cases() -> list[dict[str, Any]]:
    cases: list[dict[str, Any]] = []
    for encoding in ENCODINGS:
        for desired in DESIRED:
            for bigendian in (False, True) if desired == "passthrough" else (False,):
                data, step = _pixels(encoding, 6, 8, bigendian)
                cases.append(
                    {
                        "kind": "to_cv2",
                        "height": 6,
                        "width": 8,
                        "encoding": encoding,
                        "is_bigendian": bigendian,
                        "data": data.hex(),
                        "step": step,
                        "desired": desired,
                    }
                )
    cases.append({**cases[0], "encoding": "nonsense"})
    rng = np.random.default_rng(7)
    for dtype, shape, encoding in (
        ("u1", [4, 5, 3], "passthrough"),
        ("u1", [4, 5, 3], "bgr8"),
        ("u1", [4, 5, 3], "rgb8"),
        ("u1", [4, 5], "mono8"),
        ("u1", [4, 5], "bgr8"),
        ("<u2", [4, 5], "mono16"),
        (">u2", [4, 5], "16UC1"),
        ("<f4", [4, 5], "32FC1"),
        ("<f4", [4, 5], "passthrough"),
        ("<f8", [3, 2, 2], "passthrough"),
        ("i1", [3, 2, 4], "passthrough"),
        ("u1", [4, 5, 4], "bgra8"),
        ("u1", [4, 5, 4], "32FC1"),
        ("u1", [4, 5], "nonsense"),
    ):
        size = int(np.prod(shape)) * np.dtype(dtype).itemsize
        data = rng.integers(0, 255, size=size, endpoint=True).astype(np.uint8).tobytes()
        cases.append(
            {
                "kind": "to_msg",
                "dtype": dtype,
                "shape": shape,
                "encoding": encoding,
                "data": data.hex(),
            }
        )
    picture = np.zeros((16, 24, 3), np.uint8)
    picture[4:12, 6:18] = (30, 200, 90)
    for fmt, desired in (
        ("png", "passthrough"),
        ("png", "rgb8"),
        ("jpg", "passthrough"),
        ("png", "mono8"),
    ):
        cases.append(
            {"kind": "compressed", "dtype": "u1", "shape": [16, 24, 3], "format": fmt,
             "desired": desired, "data": picture.tobytes().hex()}
        )  # fmt: skip
    return cases


@pytest.mark.skipif(
    missing_debian_ros("cv_bridge, sensor_msgs.msg") is not None,
    reason=str(missing_debian_ros("cv_bridge, sensor_msgs.msg")),
)
def test_agrees_with_debian_cv_bridge() -> None:
    cases = _cases()
    run = subprocess.run(
        [str(ROS_PYTHON), str(ORACLE)],
        input=json.dumps(cases),
        capture_output=True,
        text=True,
        check=True,
        timeout=120,
    )
    theirs = json.loads(run.stdout)
    bridge = CvBridge()
    image, compressed = (
        message_class("sensor_msgs/Image"),
        message_class("sensor_msgs/CompressedImage"),
    )
    disagreements = []
    for case, their in zip(cases, theirs, strict=True):
        ours = answer(case, bridge, image, compressed)
        if case["kind"] == "compressed" and case["format"] == "jpg" and "image" in ours:
            # JPEG coders of two OpenCV versions may round a pixel differently
            a = np.frombuffer(bytes.fromhex(ours["image"]["data"]), np.uint8).astype(int)
            b = np.frombuffer(bytes.fromhex(their["image"]["data"]), np.uint8).astype(int)
            assert np.abs(a - b).max() <= 2
            ours["image"]["data"] = their["image"]["data"]
        if ours != their:
            short = {k: v for k, v in case.items() if k != "data"}
            disagreements.append((short, ours, their))
    assert not disagreements, disagreements[:3]
    assert sum("error" in t for t in theirs) >= 20  # the errors were compared too


def test_errors_are_cv_bridge_errors() -> None:
    bridge = CvBridge()
    msg: Any = message_class("sensor_msgs/Image")()
    msg.height, msg.width, msg.encoding, msg.step = 4, 4, "rgb8", 12
    msg.data = bytes(10)
    with pytest.raises(CvBridgeError, match="needs 48 bytes of data, has 10"):
        bridge.imgmsg_to_cv2(msg)
    msg.encoding = "jpeg"
    with pytest.raises(CvBridgeError, match=r"Unrecognized image encoding \[jpeg\]"):
        bridge.imgmsg_to_cv2(msg)
    with pytest.raises(TypeError, match="not a numpy array"):
        bridge.cv2_to_imgmsg([[1, 2]])
    bad: Any = message_class("sensor_msgs/CompressedImage")()
    bad.format, bad.data = "jpeg", b"not a picture"
    with pytest.raises(CvBridgeError, match="not an image OpenCV can decode"):
        bridge.compressed_imgmsg_to_cv2(bad)


def test_padded_step_is_honoured() -> None:
    bridge = CvBridge()
    msg: Any = message_class("sensor_msgs/Image")()
    msg.height, msg.width, msg.encoding, msg.step = 2, 3, "mono8", 4
    msg.data = bytes([1, 2, 3, 99, 4, 5, 6])
    assert bridge.imgmsg_to_cv2(msg).tolist() == [[1, 2, 3], [4, 5, 6]]
