"""Pictures of ``sensor_msgs/Image`` and ``sensor_msgs/CompressedImage`` messages, as
rqt_image_view shows them: colour as it is, grey as grey, and depth (16UC1 millimetres,
32FC1 metres) scaled over the frame's range through a colour map, nearest blue, far red,
unknown (0 or NaN) black."""

from __future__ import annotations

import io
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from belvedere.errors import BelvedereError

__all__ = ["IMAGE_ENCODINGS", "ImageError", "compressed_rgb", "depth_rgb", "image_rgb"]

Rgb = NDArray[np.uint8]

_COLOUR: Final = {"rgb8": (3, False), "bgr8": (3, True), "rgba8": (4, False), "bgra8": (4, True)}
_GREY: Final = {"mono8": np.uint8, "8uc1": np.uint8, "mono16": np.dtype("<u2")}
_DEPTH: Final = {"16uc1": np.dtype("<u2"), "32fc1": np.dtype("<f4")}
IMAGE_ENCODINGS: Final = (*_COLOUR, "mono8", "8UC1", "mono16", "16UC1", "32FC1")
"""The encodings shown (sensor_msgs/image_encodings' names)."""

# A perceptual ramp (turbo's stops, sampled): blue near, red far, as rqt_image_view's
# colour-mapped depth reads.
_RAMP: Final = np.array(
    [
        (48, 18, 59),
        (70, 107, 227),
        (41, 187, 236),
        (48, 241, 153),
        (164, 252, 60),
        (238, 207, 58),
        (251, 128, 34),
        (206, 45, 4),
        (122, 4, 3),
    ],
    dtype=np.float32,
)


class ImageError(BelvedereError):
    """An image message that cannot be shown: its encoding, or a size its data lacks."""


def _rows(msg: Any, dtype: Any, channels: int) -> NDArray[Any]:
    """The pixels of ``msg`` as (height, width[, channels]) of ``dtype``, its row padding
    (``step``) dropped."""
    item = np.dtype(dtype).itemsize * channels
    height, width, step = int(msg.height), int(msg.width), int(msg.step)
    data = np.frombuffer(bytes(msg.data), dtype=np.uint8)
    if step < width * item or data.size < height * step:
        msg_text = (
            f"{msg.encoding} image of {width} x {height} with step {step} needs "
            f"{height * max(step, width * item)} bytes, has {data.size}"
        )
        raise ImageError(msg_text)
    rows = data[: height * step].reshape(height, step)[:, : width * item]
    pixels = np.ascontiguousarray(rows).view(dtype)
    shape = (height, width) if channels == 1 else (height, width, channels)
    shaped: NDArray[Any] = pixels.reshape(shape)
    return shaped


def depth_rgb(depth: NDArray[Any]) -> Rgb:
    """Depths (any unit; 0 and NaN unknown) through the colour map, over their own range."""
    values = depth.astype(np.float32)
    known = np.isfinite(values) & (values > 0)
    rgb = np.zeros((*values.shape, 3), dtype=np.uint8)
    if not known.any():
        return rgb
    near, far = float(values[known].min()), float(values[known].max())
    scaled = (values[known] - near) / max(far - near, 1e-9) * (len(_RAMP) - 1)
    low = np.minimum(scaled.astype(np.int32), len(_RAMP) - 2)
    frac = (scaled - low)[:, None]
    rgb[known] = (_RAMP[low] * (1 - frac) + _RAMP[low + 1] * frac).astype(np.uint8)
    return rgb


def image_rgb(msg: Any) -> Rgb:
    """A ``sensor_msgs/Image`` as (height, width, 3) RGB bytes.

    Raises:
        ImageError: an encoding not shown, or data shorter than its size says.
    """
    encoding = str(msg.encoding).lower()
    if encoding in _COLOUR:
        channels, reverse = _COLOUR[encoding]
        pixels = _rows(msg, np.uint8, channels)[..., :3]
        return np.ascontiguousarray(pixels[..., ::-1] if reverse else pixels)
    if encoding in _GREY:
        grey = _rows(msg, _GREY[encoding], 1)
        if grey.dtype != np.uint8:
            grey = (grey >> 8).astype(np.uint8)
        return np.repeat(grey[..., None], 3, axis=2)
    if encoding in _DEPTH:
        return depth_rgb(_rows(msg, _DEPTH[encoding], 1))
    known = ", ".join(IMAGE_ENCODINGS)
    text = f"image encoding {msg.encoding!r} is not shown (expected one of {known})"
    raise ImageError(text)


def compressed_rgb(msg: Any) -> Rgb:
    """A ``sensor_msgs/CompressedImage`` (JPEG or PNG, as image_transport's compressed
    plugin sends) as RGB bytes.

    Raises:
        ImageError: data that is no picture PIL can read.
    """
    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(io.BytesIO(bytes(msg.data))) as picture:
            return np.asarray(picture.convert("RGB"), dtype=np.uint8)
    except (UnidentifiedImageError, OSError, ValueError) as err:
        text = f"compressed image ({msg.format!r}) is unreadable: {err}"
        raise ImageError(text) from None
