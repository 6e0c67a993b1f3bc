"""Runs under Debian's /usr/bin/python3 with its python3-cv-bridge: reads cases (JSON on
stdin), answers with what cv_bridge makes of each (JSON on stdout). Shared with
test_cv_bridge.py's own side: ``answer`` takes the bridge and the two message classes."""

from __future__ import annotations

import json
import sys
from typing import Any


def _image(result: Any) -> dict[str, Any]:
    import numpy as np

    array = np.ascontiguousarray(result)
    return {
        "shape": list(array.shape),
        "dtype": array.dtype.newbyteorder("=").name,
        "data": array.astype(array.dtype.newbyteorder("=")).tobytes().hex(),
    }


def _message(msg: Any) -> dict[str, Any]:
    return {
        "height": msg.height,
        "width": msg.width,
        "encoding": msg.encoding,
        "is_bigendian": bool(msg.is_bigendian),
        "step": msg.step,
        "data": bytes(msg.data).hex(),
    }


def answer(case: dict[str, Any], bridge: Any, image_class: Any, compressed_class: Any) -> Any:
    import numpy as np

    try:
        if case["kind"] == "to_cv2":
            msg = image_class()
            msg.height, msg.width = case["height"], case["width"]
            msg.encoding, msg.is_bigendian = case["encoding"], case["is_bigendian"]
            msg.data = bytes.fromhex(case["data"])
            msg.step = case["step"]
            return _image(bridge.imgmsg_to_cv2(msg, case["desired"]))
        if case["kind"] == "to_msg":
            array = np.frombuffer(bytes.fromhex(case["data"]), dtype=case["dtype"])
            array = array.reshape(case["shape"])
            return _message(bridge.cv2_to_imgmsg(array, case["encoding"]))
        if case["kind"] == "compressed":
            array = np.frombuffer(bytes.fromhex(case["data"]), dtype=case["dtype"])
            message = bridge.cv2_to_compressed_imgmsg(array.reshape(case["shape"]), case["format"])
            back = compressed_class()
            back.format, back.data = message.format, message.data
            return {
                "format": message.format,
                "image": _image(bridge.compressed_imgmsg_to_cv2(back, case["desired"])),
            }
    except TypeError as error:  # CvBridgeError is one
        return {"error": type(error).__name__, "text": str(error)}
    msg = f"unknown case {case['kind']}"
    raise ValueError(msg)


def main() -> None:
    import sensor_msgs.msg  # type: ignore[import-not-found]
    from cv_bridge import CvBridge

    bridge = CvBridge()
    cases = json.load(sys.stdin)
    answers = [
        answer(case, bridge, sensor_msgs.msg.Image, sensor_msgs.msg.CompressedImage)
        for case in cases
    ]
    json.dump(answers, sys.stdout)


if __name__ == "__main__":
    main()
