"""Run by Debian's /usr/bin/python3 (its cv_bridge) and by belvedere's script runner (belvedere's
cv_bridge): every conversion between encodings of generated images, as JSON on stdout. Not
imported by the tests themselves."""

import hashlib
import json
import sys
from collections.abc import Callable
from functools import partial
from typing import Any

import numpy as np
from cv_bridge import CvBridge, CvBridgeError

ENCODINGS = [
    "rgb8",
    "bgr8",
    "rgba8",
    "bgra8",
    "mono8",
    "mono16",
    "rgb16",
    "bgr16",
    "rgba16",
    "bgra16",
    "bayer_rggb8",
    "bayer_bggr8",
    "bayer_gbrg8",
    "bayer_grbg8",
    "bayer_rggb16",
    "8UC1",
    "8UC2",
    "8UC3",
    "8UC4",
    "8SC1",
    "16UC1",
    "16SC1",
    "32SC1",
    "32FC1",
    "32FC3",
    "64FC1",
    "yuv422",
]
DEPTHS = {
    "8U": "uint8",
    "8S": "int8",
    "16U": "uint16",
    "16S": "int16",
    "32S": "int32",
    "32F": "float32",
    "64F": "float64",
}
bridge = CvBridge()


def layout(encoding: str) -> tuple[str, int]:
    colour = {"rgb": 3, "bgr": 3, "rgba": 4, "bgra": 4, "mono": 1}
    for name, channels in colour.items():
        for bits in ("8", "16"):
            if encoding == name + bits:
                return ("uint8" if bits == "8" else "uint16"), channels
    if encoding.startswith("bayer_"):
        return ("uint8" if encoding.endswith("8") else "uint16"), 1
    if encoding == "yuv422":
        return "uint8", 2
    depth, _, count = encoding.partition("C")
    return DEPTHS[depth], int(count)


def image(encoding: str, seed: int) -> Any:
    dtype, channels = layout(encoding)
    rng = np.random.RandomState(seed)
    shape = (4, 6) if channels == 1 else (4, 6, channels)
    if dtype.startswith("float"):
        return (rng.rand(*shape) * 100).astype(dtype)
    info = np.iinfo(dtype)
    return rng.randint(info.min, int(info.max) + 1, size=shape).astype(dtype)


def digest(array: Any) -> list[Any]:
    array = np.asarray(array)
    return [
        list(array.shape),
        array.dtype.str,
        hashlib.sha256(np.ascontiguousarray(array).tobytes()).hexdigest()[:16],
    ]


def attempt(action: Callable[[], Any]) -> list[Any]:
    try:
        return ["ok", digest(action())]
    except CvBridgeError as err:
        return ["CvBridgeError", str(err)]
    except TypeError as err:
        return ["TypeError", str(err)]


def message(msg: Any) -> list[Any]:
    return [
        msg.encoding,
        msg.height,
        msg.width,
        msg.step,
        int(msg.is_bigendian),
        hashlib.sha256(bytes(msg.data)).hexdigest()[:16],
    ]


def round_trip(img: Any, encoding: str) -> Any:
    return bridge.imgmsg_to_cv2(bridge.cv2_to_imgmsg(img, encoding))


out: dict[str, Any] = {}
for i, src in enumerate(ENCODINGS):
    img = image(src, i)
    msg = bridge.cv2_to_imgmsg(img, src)
    out["to_msg " + src] = message(msg)
    out["passthrough msg " + src] = message(bridge.cv2_to_imgmsg(img))
    for dst in [*ENCODINGS, "passthrough", "nonsense"]:
        out[f"{src} -> {dst}"] = attempt(partial(bridge.imgmsg_to_cv2, msg, dst))
    for other in ("bgr8", "mono16", "32FC1"):
        out[f"to_msg {src} as {other}"] = attempt(partial(round_trip, img, other))
out["not an array"] = attempt(lambda: bridge.cv2_to_imgmsg([[1, 2]], "mono8"))

# a big-endian mono16 message, as some drivers send
be = bridge.cv2_to_imgmsg(image("mono16", 99).astype(">u2"), "mono16")
out["big-endian flag"] = int(be.is_bigendian)
out["big-endian decoded"] = attempt(lambda: bridge.imgmsg_to_cv2(be).astype("<u2"))
out["big-endian to mono8"] = attempt(lambda: bridge.imgmsg_to_cv2(be, "mono8"))

# compressed: what decodes from PNG (lossless) is compared, not the encoder's bytes
colour = image("bgr8", 7)
png = bridge.cv2_to_compressed_imgmsg(colour, "png")
out["png format"] = png.format
for dst in ("passthrough", "bgr8", "rgb8", "mono8", "bgra8", "mono16"):
    out["png -> " + dst] = attempt(partial(bridge.compressed_imgmsg_to_cv2, png, dst))
jpg = bridge.cv2_to_compressed_imgmsg(colour)
out["jpg format"] = jpg.format
out["jpg decodes"] = list(bridge.compressed_imgmsg_to_cv2(jpg).shape)
sys.stdout.write(json.dumps(out, sort_keys=True) + "\n")
