"""sensor_msgs/image_encodings as cv_bridge reads them: each encoding's OpenCV depth and
channel count, its bit depth, and the colour family cv_bridge converts between."""

from __future__ import annotations

import re
from typing import Final

__all__ = [
    "BAYER",
    "COLOUR",
    "DEPTHS",
    "EncodingError",
    "bit_depth",
    "channels",
    "cv_type",
    "depth_name",
    "family",
    "is_colour_format",
]

DEPTHS: Final = ("8U", "8S", "16U", "16S", "32S", "32F", "64F")
"""OpenCV's depths in the order of their codes (CV_8U is 0 ... CV_64F is 6)."""

# name: (depth, channels, family): the family names the colours cv_bridge converts between
COLOUR: Final[dict[str, tuple[str, int, str]]] = {
    "mono8": ("8U", 1, "gray"),
    "mono16": ("16U", 1, "gray"),
    "rgb8": ("8U", 3, "rgb"),
    "rgb16": ("16U", 3, "rgb"),
    "bgr8": ("8U", 3, "bgr"),
    "bgr16": ("16U", 3, "bgr"),
    "rgba8": ("8U", 4, "rgba"),
    "rgba16": ("16U", 4, "rgba"),
    "bgra8": ("8U", 4, "bgra"),
    "bgra16": ("16U", 4, "bgra"),
    "yuv422": ("8U", 2, "yuv422"),
}
BAYER: Final = ("rggb", "bggr", "gbrg", "grbg")
_GENERIC: Final = re.compile(r"(8U|8S|16U|16S|32S|32F|64F)(?:C([0-9]+))?")


class EncodingError(RuntimeError):
    """An encoding name sensor_msgs/image_encodings does not know (cv_bridge's text)."""


def _named(encoding: str) -> tuple[str, int, str | None] | None:
    if encoding in COLOUR:
        return COLOUR[encoding]
    for pattern in BAYER:
        if encoding == f"bayer_{pattern}8":
            return ("8U", 1, f"bayer_{pattern}")
        if encoding == f"bayer_{pattern}16":
            return ("16U", 1, f"bayer_{pattern}")
    return None


def cv_type(encoding: str) -> tuple[str, int]:
    """(depth name, channels) of an encoding, as cv_bridge's getCvType."""
    named = _named(encoding)
    if named is not None:
        return named[0], named[1]
    match = _GENERIC.fullmatch(encoding)
    if match is None:
        msg = f"Unrecognized image encoding [{encoding}]"
        raise EncodingError(msg)
    return match[1], int(match[2] or 1)


def depth_name(encoding: str) -> str:
    return cv_type(encoding)[0]


def channels(encoding: str) -> int:
    return cv_type(encoding)[1]


def bit_depth(encoding: str) -> int:
    return int(re.sub(r"[USF]", "", depth_name(encoding)))


def is_colour_format(encoding: str) -> bool:
    """Colour, mono, Bayer or YUV: an encoding whose channels mean colours."""
    return _named(encoding) is not None


def family(encoding: str) -> str | None:
    """The colour family cv_bridge converts between (gray, rgb, ..., bayer_rggb), or None."""
    named = _named(encoding)
    return None if named is None else named[2]
