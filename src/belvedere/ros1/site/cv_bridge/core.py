"""``CvBridge``: images between ROS messages and OpenCV (numpy) arrays.

An encoding names a layout: a colour one (``rgb8``, ``bgra16``, ``mono8``, ``bayer_rggb8``,
``yuv422``…) or an OpenCV type (``8UC3``, ``32FC1``…). Converting between colour encodings
goes through OpenCV's ``cvtColor`` (the depth scaled first, 8 ↔ 16 bits by 65535/255); an
OpenCV type converts only to one with as many channels."""

from __future__ import annotations

import re
import sys
from typing import Any

import numpy as np

__all__ = ["CvBridge", "CvBridgeError"]


class CvBridgeError(TypeError):
    """A conversion that cannot be made (ROS's is a TypeError too)."""


# colour encoding -> (depth, channels)
_COLOUR: dict[str, tuple[str, int]] = {}
for _bits in ("8", "16"):
    _COLOUR.update(
        {
            f"rgb{_bits}": (f"{_bits}U", 3),
            f"bgr{_bits}": (f"{_bits}U", 3),
            f"rgba{_bits}": (f"{_bits}U", 4),
            f"bgra{_bits}": (f"{_bits}U", 4),
            f"mono{_bits}": (f"{_bits}U", 1),
        }
    )
    for _pattern in ("rggb", "bggr", "gbrg", "grbg"):
        _COLOUR[f"bayer_{_pattern}{_bits}"] = (f"{_bits}U", 1)
_COLOUR["yuv422"] = ("8U", 2)
_COLOUR["yuv422_yuy2"] = ("8U", 2)

_DEPTHS = {
    "8U": "uint8",
    "8S": "int8",
    "16U": "uint16",
    "16S": "int16",
    "32S": "int32",
    "32F": "float32",
    "64F": "float64",
}
_DEPTH_OF = {v: k for k, v in _DEPTHS.items()}
_CV_TYPE = re.compile(r"^(8U|8S|16U|16S|32S|32F|64F)(?:C([0-9]+))?$")


def _layout(encoding: str) -> tuple[str, int]:
    """(OpenCV depth, channels) of an encoding."""
    if encoding in _COLOUR:
        return _COLOUR[encoding]
    match = _CV_TYPE.match(encoding)
    if match is None:
        msg = f"Unknown encoding {encoding}"
        raise CvBridgeError(msg)
    return match.group(1), int(match.group(2) or 1)


def _is_colour(encoding: str) -> bool:
    return encoding in _COLOUR


def _format(encoding: str) -> str:
    """The colour family an encoding belongs to (``BGR``, ``GRAY``, ``BAYER_RGGB``…)."""
    base = encoding.rstrip("0123456789")
    return {"mono": "GRAY", "yuv": "YUV422", "yuv422_yuy": "YUV422"}.get(base, base.upper())


# (from, to) colour families -> OpenCV cvtColor code names, in order
_CODES: dict[tuple[str, str], tuple[str, ...]] = {}
for _a, _b in (
    ("BGR", "RGB"),
    ("BGR", "BGRA"),
    ("BGR", "RGBA"),
    ("RGB", "RGBA"),
    ("RGB", "BGRA"),
    ("BGRA", "RGBA"),
):
    _CODES[_a, _b] = (f"COLOR_{_a}2{_b}",)
    _CODES[_b, _a] = (f"COLOR_{_b}2{_a}",)
for _c in ("BGR", "RGB", "BGRA", "RGBA"):
    _CODES["GRAY", _c] = (f"COLOR_GRAY2{_c}",)
    _CODES[_c, "GRAY"] = (f"COLOR_{_c}2GRAY",)
# OpenCV names a Bayer pattern by its second row: ROS's rggb is OpenCV's BG
for _ros, _cv in (("RGGB", "BG"), ("BGGR", "RG"), ("GBRG", "GR"), ("GRBG", "GB")):
    _CODES[f"BAYER_{_ros}", "GRAY"] = (f"COLOR_Bayer{_cv}2GRAY",)
    _CODES[f"BAYER_{_ros}", "BGR"] = (f"COLOR_Bayer{_cv}2BGR",)
    _CODES[f"BAYER_{_ros}", "RGB"] = (f"COLOR_Bayer{_cv}2RGB",)
for _c in ("GRAY", "BGR", "RGB", "BGRA", "RGBA"):
    _CODES["YUV422", _c] = (f"COLOR_YUV2{_c}_UYVY",)


def _cv2() -> Any:
    import cv2

    return cv2


def _convert(image: np.ndarray, src: str, dst: str) -> np.ndarray:
    """cv_bridge's ``cvtColor2``: ``image`` in encoding ``src`` as encoding ``dst``."""
    src_depth, src_channels = _layout(src)
    dst_depth, dst_channels = _layout(dst)
    if src == dst:
        return image.copy()
    src_colour, dst_colour = _is_colour(src), _is_colour(dst)
    if not src_colour:
        if dst_colour:
            msg = (
                f"[{src}] is not a color format. but [{dst}] is. The conversion does not make sense"
            )
            raise CvBridgeError(msg)
        if src_channels != dst_channels:
            msg = f"[{src}] and [{dst}] do not have the same number of channel"
            raise CvBridgeError(msg)
    elif not dst_colour and src_channels != dst_channels:
        msg = (
            f"[{src}] is a color format but [{dst}] is not so they must have the same OpenCV "
            "type, CV_8UC3, CV16UC1 ...."
        )
        raise CvBridgeError(msg)
    if not (src_colour and dst_colour):
        # an OpenCV type on either side: the values in the other depth
        return np.ascontiguousarray(
            _scaled(image, _DEPTHS[dst_depth], _scale(src_depth, dst_depth))
        )
    out = image
    key = (_format(src), _format(dst))
    if key[0] == key[1] and key[0].startswith("BAYER_") and src_depth != dst_depth:
        msg = f"Unsupported conversion from [{src}] to [{dst}]"
        raise CvBridgeError(msg)
    if key[0] != key[1]:
        codes = _CODES.get(key)
        if codes is None:
            msg = f"Unsupported conversion from [{src}] to [{dst}]"
            raise CvBridgeError(msg)
        cv2 = _cv2()
        try:
            for name in codes:
                out = cv2.cvtColor(out, getattr(cv2, name))
        except cv2.error as err:
            raise CvBridgeError(str(err)) from None
    if src_depth != dst_depth:
        out = _scaled(out, _DEPTHS[dst_depth], _scale(src_depth, dst_depth))  # colour first
    return np.ascontiguousarray(out)


def _scale(src_depth: str, dst_depth: str) -> float:
    """8 <-> 16 bits (signed or not) are scaled to the other's range, as cv_bridge does."""
    bits = {"8U": 8, "8S": 8, "16U": 16, "16S": 16}
    pair = (bits.get(src_depth), bits.get(dst_depth))
    if pair == (8, 16):
        return 65535.0 / 255.0
    if pair == (16, 8):
        return 255.0 / 65535.0
    return 1.0


def _scaled(image: np.ndarray, dtype: str, scale: float) -> np.ndarray:
    """OpenCV's ``convertTo``: scaled, rounded to nearest and saturated into ``dtype``."""
    target = np.dtype(dtype)
    values = image.astype(np.float64) * scale
    if target.kind in "iu":
        info = np.iinfo(target)
        values = np.clip(np.rint(values), info.min, info.max)
    return values.astype(target)


class CvBridge:
    """Images between ROS and OpenCV, as ROS's ``cv_bridge.CvBridge``."""

    def __init__(self) -> None:
        self.numpy_type_to_cvtype = dict(_DEPTH_OF)

    # --- types ---------------------------------------------------------------------------------
    def dtype_with_channels_to_cvtype2(self, dtype: Any, n_channels: int) -> str:
        return f"{self.numpy_type_to_cvtype[np.dtype(dtype).name]}C{n_channels}"

    def encoding_to_dtype_with_channels(self, encoding: str) -> tuple[str, int]:
        depth, channels = _layout(encoding)
        return _DEPTHS[depth], channels

    # --- Image ----------------------------------------------------------------------------------
    def imgmsg_to_cv2(self, img_msg: Any, desired_encoding: str = "passthrough") -> np.ndarray:
        name, channels = self.encoding_to_dtype_with_channels(img_msg.encoding)
        dtype = np.dtype(name).newbyteorder(">" if img_msg.is_bigendian else "<")
        data = img_msg.data
        buffer = np.asarray(data, dtype=np.uint8) if isinstance(data, list) else data
        if not isinstance(buffer, (bytes, bytearray, memoryview)):
            buffer = np.ascontiguousarray(buffer).tobytes()
        row = int(img_msg.step) // dtype.itemsize
        if channels == 1:
            shape: tuple[int, ...] = (img_msg.height, row)
        else:
            shape = (img_msg.height, row // channels, channels)
        image = np.ndarray(shape=shape, dtype=dtype, buffer=buffer)
        image = np.ascontiguousarray(image[: img_msg.height, : img_msg.width])
        if bool(img_msg.is_bigendian) == (sys.byteorder == "little"):
            image = image.byteswap().view(image.dtype.newbyteorder())
        if desired_encoding == "passthrough":
            return image
        return _convert(image, img_msg.encoding, desired_encoding)

    def cv2_to_imgmsg(self, cvim: Any, encoding: str = "passthrough", header: Any = None) -> Any:
        if not isinstance(cvim, (np.ndarray, np.generic)):
            msg = "Your input type is not a numpy array"
            raise TypeError(msg)
        from sensor_msgs.msg import Image

        img_msg = Image()
        img_msg.height = cvim.shape[0]
        img_msg.width = cvim.shape[1]
        if header is not None:
            img_msg.header = header
        channels = 1 if cvim.ndim < 3 else cvim.shape[2]
        cv_type = self.dtype_with_channels_to_cvtype2(cvim.dtype, channels)
        if encoding == "passthrough":
            img_msg.encoding = cv_type
        else:
            img_msg.encoding = encoding
            depth, wanted = _layout(encoding)
            if f"{depth}C{wanted}" != cv_type:
                msg = f"encoding specified as {encoding}, but image has incompatible type {cv_type}"
                raise CvBridgeError(msg)
        if cvim.dtype.byteorder == ">":
            img_msg.is_bigendian = True
        img_msg.data = np.ascontiguousarray(cvim).tobytes()
        img_msg.step = len(img_msg.data) // img_msg.height
        return img_msg

    # --- CompressedImage ------------------------------------------------------------------------
    def compressed_imgmsg_to_cv2(
        self, cmprs_img_msg: Any, desired_encoding: str = "passthrough"
    ) -> np.ndarray:
        cv2 = _cv2()
        buffer = np.frombuffer(bytes(cmprs_img_msg.data), dtype=np.uint8).reshape(1, -1)
        image = cv2.imdecode(buffer, cv2.IMREAD_UNCHANGED)
        if desired_encoding == "passthrough":
            return image  # type: ignore[no-any-return]
        return _convert(image, "bgr8", desired_encoding)

    def cv2_to_compressed_imgmsg(self, cvim: Any, dst_format: str = "jpg") -> Any:
        if not isinstance(cvim, (np.ndarray, np.generic)):
            msg = "Your input type is not a numpy array"
            raise TypeError(msg)
        from sensor_msgs.msg import CompressedImage

        cv2 = _cv2()
        msg_out = CompressedImage()
        msg_out.format = dst_format
        try:
            ok, encoded = cv2.imencode("." + dst_format, cvim)
        except cv2.error as err:
            raise CvBridgeError(str(err)) from None
        if not ok:
            msg = f"cannot encode the image as {dst_format}"
            raise CvBridgeError(msg)
        msg_out.data = encoded.tobytes()
        return msg_out
