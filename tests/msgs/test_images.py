"""Image messages as rqt_image_view shows them: every encoding it shows, row padding, depth
through the colour map, and one clear error for what cannot be shown."""

from __future__ import annotations

import io

import numpy as np
import pytest
from PIL import Image

from belvedere.msgs import ImageError, compressed_rgb, image_rgb, message_from_data


def image(encoding: str, pixels: np.ndarray, *, pad: int = 0) -> object:
    height, width = pixels.shape[:2]
    rows = pixels.reshape(height, -1).view(np.uint8)
    step = rows.shape[1] + pad
    data = np.zeros((height, step), dtype=np.uint8)
    data[:, : rows.shape[1]] = rows
    fields = {"height": height, "width": width, "encoding": encoding, "step": step}
    return message_from_data("sensor_msgs/Image", {**fields, "data": data.reshape(-1).tolist()})


RGB = np.arange(2 * 3 * 3, dtype=np.uint8).reshape(2, 3, 3) * 10


def test_colour_encodings_keep_their_colours_and_drop_row_padding() -> None:
    assert np.array_equal(image_rgb(image("rgb8", RGB, pad=3)), RGB)
    assert np.array_equal(image_rgb(image("bgr8", RGB[..., ::-1].copy())), RGB)
    rgba = np.concatenate([RGB, np.full((2, 3, 1), 255, np.uint8)], axis=2)
    assert np.array_equal(image_rgb(image("rgba8", rgba)), RGB)


def test_grey_is_grey() -> None:
    grey = np.array([[0, 128], [200, 255]], dtype=np.uint8)
    shown = image_rgb(image("mono8", grey, pad=2))
    assert np.array_equal(shown[..., 0], grey)
    assert np.array_equal(shown[..., 2], grey)


@pytest.mark.parametrize(
    ("encoding", "depth"),
    [
        ("32FC1", np.array([[0.5, 1.0], [4.0, np.nan]], dtype="<f4")),
        ("16UC1", np.array([[500, 1000], [4000, 0]], dtype="<u2")),
    ],
)
def test_depth_is_coloured_near_blue_far_red_unknown_black(
    encoding: str, depth: np.ndarray
) -> None:
    shown = image_rgb(image(encoding, depth))
    near, far, unknown = shown[0, 0], shown[1, 0], shown[1, 1]
    assert near[2] > near[0]
    assert far[0] > far[2]
    assert list(unknown) == [0, 0, 0]
    assert not np.array_equal(shown[0, 1], near)


def test_an_encoding_not_shown_or_short_data_is_one_error() -> None:
    with pytest.raises(ImageError, match=r"'bayer_rggb8' is not shown \(expected one of"):
        image_rgb(image("bayer_rggb8", RGB[..., 0].copy()))
    short = message_from_data(
        "sensor_msgs/Image",
        {"height": 4, "width": 4, "encoding": "rgb8", "step": 12, "data": [0] * 10},
    )
    with pytest.raises(ImageError, match="needs 48 bytes, has 10"):
        image_rgb(short)


def test_compressed_images_are_decoded() -> None:
    buffer = io.BytesIO()
    Image.fromarray(np.full((8, 8, 3), (250, 0, 0), np.uint8)).save(buffer, format="PNG")
    msg = message_from_data(
        "sensor_msgs/CompressedImage", {"format": "png", "data": list(buffer.getvalue())}
    )
    assert compressed_rgb(msg)[4, 4].tolist() == [250, 0, 0]
    bad = message_from_data("sensor_msgs/CompressedImage", {"format": "jpeg", "data": [1, 2]})
    with pytest.raises(ImageError, match="compressed image \\('jpeg'\\) is unreadable"):
        compressed_rgb(bad)
