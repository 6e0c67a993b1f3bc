"""ROS 1's ``cv_bridge``: ``CvBridge`` between sensor_msgs/Image (and CompressedImage) and
OpenCV's numpy images, with cv_bridge's conversions between encodings and its error texts.

Conversions follow cv_bridge's C++ ``cvtColor``: between colour families through OpenCV's
colour codes, within a family by depth (8 <-> 16 bits scaled by 65535/255), and between
formats without colour meaning (``32FC1`` ...) only to the same channel count. The original
reads a row as ``width`` pixels, ignoring ``step``; this one honours a padded ``step`` (as
later cv_bridge does) and says so when the data is shorter than the image needs.
"""

from __future__ import annotations

import sys
from typing import Any, Final

import cv2
import numpy as np
from numpy.typing import NDArray

from belvedere.ros1 import message_class
from belvedere.ros1._encodings import (
    DEPTHS,
    EncodingError,
    bit_depth,
    channels,
    cv_type,
    family,
    is_colour_format,
)

__all__ = ["CvBridge", "CvBridgeError"]

_NUMPY: Final = {
    "8U": "uint8",
    "8S": "int8",
    "16U": "uint16",
    "16S": "int16",
    "32S": "int32",
    "32F": "float32",
    "64F": "float64",
}
_CV: Final = {numpy: cv for cv, numpy in _NUMPY.items()}
_SAME: Final = -1


class CvBridgeError(TypeError):
    """This is the error raised by :class:`cv_bridge.CvBridge` methods when they fail."""


def _codes() -> dict[tuple[str, str], list[int]]:
    """cv_bridge's table of OpenCV colour codes between families."""
    colours = ("gray", "rgb", "bgr", "rgba", "bgra")
    names = {"gray": "GRAY", "rgb": "RGB", "bgr": "BGR", "rgba": "RGBA", "bgra": "BGRA"}
    table: dict[tuple[str, str], list[int]] = {(f, f): [_SAME] for f in (*colours, "yuv422")}
    for src in colours:
        for dst in colours:
            if src != dst:
                table[(src, dst)] = [getattr(cv2, f"COLOR_{names[src]}2{names[dst]}")]
    for dst in colours:
        table[("yuv422", dst)] = [getattr(cv2, f"COLOR_YUV2{names[dst]}_UYVY")]
    # OpenCV names a Bayer pattern by its second row's first two pixels
    for pattern, cv_name in (("rggb", "BG"), ("bggr", "RG"), ("gbrg", "GR"), ("grbg", "GB")):
        for dst in ("gray", "rgb", "bgr"):
            table[(f"bayer_{pattern}", dst)] = [getattr(cv2, f"COLOR_Bayer{cv_name}2{names[dst]}")]
    return table


_CODES: Final = _codes()


def _conversion(src: str, dst: str) -> list[int]:
    """The steps from ``src`` to ``dst`` (cv_bridge's getConversionCode), or its error."""
    src_colour, dst_colour = is_colour_format(src), is_colour_format(dst)
    same_channels = channels(src) == channels(dst)
    if not src_colour:
        if dst_colour:
            msg = (
                f"[{src}] is not a color format. but [{dst}] is. The conversion does not make sense"
            )
            raise CvBridgeError(msg)
        if not same_channels:
            msg = f"[{src}] and [{dst}] do not have the same number of channel"
            raise CvBridgeError(msg)
        return [_SAME]
    if not dst_colour:
        if not same_channels:
            msg = (
                f"[{src}] is a color format but [{dst}] is not so they must have the same "
                "OpenCV type, CV_8UC3, CV16UC1 ...."
            )
            raise CvBridgeError(msg)
        return [_SAME]
    steps = _CODES.get((family(src) or "", family(dst) or ""))
    if steps is None:
        msg = f"Unsupported conversion from [{src}] to [{dst}]"
        raise CvBridgeError(msg)
    if bit_depth(src) != bit_depth(dst) and family(src) != family(dst):
        return [*steps, _SAME]
    return list(steps)


def _convert(image: NDArray[Any], src: str, dst: str) -> NDArray[Any]:
    """``image`` (in ``src``) in encoding ``dst``: cv_bridge's cvtColor."""
    try:
        cv_type(src)
    except EncodingError as error:
        raise CvBridgeError(str(error)) from None
    try:
        cv_type(dst)
    except EncodingError:
        # cv_bridge's cvtColor2 names a desired encoding it does not know so
        msg = f"Unknown encoding {dst}"
        raise CvBridgeError(msg) from None
    if src == dst:
        return image.copy()
    for step in _conversion(src, dst):
        if step != _SAME:
            image = cv2.cvtColor(image, step)
            continue
        dtype = np.dtype(_NUMPY[cv_type(dst)[0]])
        scale = {(8, 16): 65535.0 / 255.0, (16, 8): 255.0 / 65535.0}.get(
            (bit_depth(src), bit_depth(dst)), 1.0
        )
        # convertTo: scaled, rounded to nearest and saturated into the target depth
        if image.dtype == dtype and scale == 1.0:
            continue
        converted = image.astype(np.float64) * scale
        if dtype.kind in "iu":
            info = np.iinfo(dtype)
            converted = np.clip(np.rint(converted), info.min, info.max)
        image = converted.astype(dtype)
    return image


def _bytes(data: Any) -> bytes:
    if isinstance(data, str):
        return data.encode("latin-1")
    return bytes(data)


class CvBridge:
    """Converts between OpenCV images (numpy arrays) and ROS Image messages."""

    def __init__(self) -> None:
        self.cvtype_to_name: dict[int, str] = {}
        self.cvdepth_to_numpy_depth = {code: _NUMPY[name] for code, name in enumerate(DEPTHS)}
        for depth in DEPTHS:
            for count in (1, 2, 3, 4):
                name = f"{depth}C{count}"
                self.cvtype_to_name[int(getattr(cv2, f"CV_{name}"))] = name
        self.numpy_type_to_cvtype: dict[str, str] = {**_CV, **_NUMPY}

    def dtype_with_channels_to_cvtype2(self, dtype: np.dtype[Any], n_channels: int) -> str:
        if dtype.name not in _CV:
            msg = f"OpenCV has no image type of {dtype.name} (one of {', '.join(_CV)})"
            raise CvBridgeError(msg)
        return f"{_CV[dtype.name]}C{n_channels}"

    def cvtype2_to_dtype_with_channels(self, cvtype: int) -> tuple[str, int]:
        return _NUMPY[DEPTHS[cvtype & 7]], (cvtype >> 3) + 1

    def encoding_to_cvtype2(self, encoding: str) -> int:
        try:
            depth, count = cv_type(encoding)
        except EncodingError as error:
            raise CvBridgeError(str(error)) from None
        return DEPTHS.index(depth) + ((count - 1) << 3)

    def encoding_to_dtype_with_channels(self, encoding: str) -> tuple[str, int]:
        return self.cvtype2_to_dtype_with_channels(self.encoding_to_cvtype2(encoding))

    def imgmsg_to_cv2(self, img_msg: Any, desired_encoding: str = "passthrough") -> Any:
        """A sensor_msgs/Image as a numpy image, in ``desired_encoding`` unless
        ``"passthrough"`` (one channel: shape (height, width))."""
        name, count = self.encoding_to_dtype_with_channels(img_msg.encoding)
        dtype = np.dtype(name).newbyteorder(">" if img_msg.is_bigendian else "<")
        height, width, step = int(img_msg.height), int(img_msg.width), int(img_msg.step)
        data = _bytes(img_msg.data)
        row = width * count * dtype.itemsize
        step = max(step, row)
        if len(data) < height * step - (step - row):
            msg = (
                f"{img_msg.encoding} image of {width} x {height} (step {step}) needs "
                f"{height * step - (step - row)} bytes of data, has {len(data)}"
            )
            raise CvBridgeError(msg)
        rows = np.frombuffer(data, np.uint8, count=max(height * step - (step - row), 0))
        if height:
            rows = np.pad(rows, (0, step - row)).reshape(height, step)[:, :row]
        pixels = np.ascontiguousarray(rows).view(dtype)
        shape = (height, width) if count == 1 else (height, width, count)
        image: NDArray[Any] = pixels.reshape(shape)
        if dtype.byteorder not in ("=", "|") and img_msg.is_bigendian == (
            sys.byteorder == "little"
        ):
            image = image.astype(dtype.newbyteorder("="))
        if desired_encoding == "passthrough":
            return image
        return _convert(image, img_msg.encoding, desired_encoding)

    def compressed_imgmsg_to_cv2(
        self, cmprs_img_msg: Any, desired_encoding: str = "passthrough"
    ) -> Any:
        """A sensor_msgs/CompressedImage decoded (as OpenCV reads it: colour as bgr8)."""
        buffer = np.frombuffer(_bytes(cmprs_img_msg.data), np.uint8)
        image = cv2.imdecode(buffer, cv2.IMREAD_UNCHANGED) if buffer.size else None
        if image is None:
            msg = (
                f"compressed image of {buffer.size} bytes (format {cmprs_img_msg.format!r}) "
                "is not an image OpenCV can decode"
            )
            raise CvBridgeError(msg)
        if desired_encoding == "passthrough":
            return image
        return _convert(image, "bgr8", desired_encoding)

    def cv2_to_compressed_imgmsg(self, cvim: Any, dst_format: str = "jpg") -> Any:
        """A numpy image as a sensor_msgs/CompressedImage of ``dst_format`` (jpg, png, ...)."""
        if not isinstance(cvim, np.ndarray | np.generic):
            msg = "Your input type is not a numpy array"
            raise TypeError(msg)
        message: Any = message_class("sensor_msgs/msg/CompressedImage")()
        message.format = dst_format
        try:
            ok, encoded = cv2.imencode(f".{dst_format}", np.asarray(cvim))
        except cv2.error as error:
            msg = f"cannot encode the image as {dst_format}: {error}"
            raise CvBridgeError(msg) from None
        if not ok:
            msg = f"OpenCV could not encode the image as {dst_format}"
            raise CvBridgeError(msg)
        message.data = encoded.tobytes()
        return message

    def cv2_to_imgmsg(
        self, cvim: NDArray[Any] | Any, encoding: str = "passthrough", header: Any = None
    ) -> Any:
        """A numpy image as a sensor_msgs/Image (``encoding`` must fit its type)."""
        if not isinstance(cvim, np.ndarray | np.generic):
            msg = "Your input type is not a numpy array"
            raise TypeError(msg)
        message: Any = message_class("sensor_msgs/msg/Image")()
        message.height = cvim.shape[0]
        message.width = cvim.shape[1]
        if header is not None:
            message.header = header
        count = 1 if len(cvim.shape) < 3 else cvim.shape[2]
        cv_name = self.dtype_with_channels_to_cvtype2(cvim.dtype, count)
        if encoding == "passthrough":
            message.encoding = cv_name
        else:
            message.encoding = encoding
            wanted = self.encoding_to_cvtype2(encoding)
            if self.cvtype_to_name.get(wanted) != cv_name:
                msg = f"encoding specified as {encoding}, but image has incompatible type {cv_name}"
                raise CvBridgeError(msg)
        if cvim.dtype.byteorder == ">":
            message.is_bigendian = True
        message.data = np.ascontiguousarray(cvim).tobytes()
        message.step = len(message.data) // message.height if message.height else 0
        return message
