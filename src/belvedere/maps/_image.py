"""Map images read as map_server's image loader (SDL_image) sees them: bytes per pixel.

map_server averages the bytes of each pixel as SDL_image hands them over, so what matters is
the channels SDL gives, not the colours an image viewer shows:

- greyscale (PGM, 8-bit PNG) is one byte, the grey value; a PGM whose maxval is below 255
  is stretched to 0..255 as SDL_image does (``v * 255 // maxval``); 16-bit samples keep
  their high byte (libpng's ``strip_16``);
- a palette image is one byte, the palette *index* (SDL keeps indexed surfaces), unless it
  has transparency, which makes it RGBA;
- grey with alpha becomes RGBA (grey, grey, grey, alpha); RGB and RGBA are as stored.

PGM (``P2`` plain and ``P5`` raw) is read here, with errors that say what is wrong; every
other format goes through Pillow.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt

__all__ = ["ImageError", "MapImage", "read_map_image"]


class ImageError(Exception):
    """An image that cannot be read (the message says why, not where)."""


@dataclass(frozen=True)
class MapImage:
    """Pixels as map_server's loader sees them."""

    pixels: npt.NDArray[np.uint8]
    """``(height, width, channels)`` bytes, top row first."""
    has_alpha: bool
    """Whether the last channel is alpha (SDL's ``Amask``)."""


_TOKEN = re.compile(rb"\s*(?:#[^\n\r]*[\n\r]\s*)*")
"""Whitespace and comments between PGM header fields."""


def _pgm_header(raw: bytes) -> tuple[bytes, int, int, int, int]:
    """(magic, width, height, maxval, offset of the raster)."""
    magic = raw[:2]
    pos = 2
    values: list[int] = []
    names = ("width", "height", "maxval")
    for name in names:
        skip = _TOKEN.match(raw, pos)
        pos = skip.end() if skip else pos
        digits = re.compile(rb"\d+").match(raw, pos)
        if digits is None:
            if pos >= len(raw):
                msg = f"the PGM header ends before its {name}"
            else:
                found = raw[pos : pos + 10].decode("latin-1")
                msg = f"the PGM header's {name} is not a number (found {found!r})"
            raise ImageError(msg)
        values.append(int(digits.group()))
        pos = digits.end()
    width, height, maxval = values
    if width <= 0 or height <= 0:
        msg = f"the PGM image is {width} x {height} pixels: a map needs at least one"
        raise ImageError(msg)
    if not 0 < maxval < 65536:
        msg = f"the PGM maxval is {maxval}: it must be 1 to 65535"
        raise ImageError(msg)
    if pos >= len(raw) or raw[pos : pos + 1] not in (b" ", b"\t", b"\n", b"\r", b"\f", b"\v"):
        msg = "the PGM header does not end with a whitespace after its maxval"
        raise ImageError(msg)
    return magic, width, height, maxval, pos + 1


def _read_pgm(raw: bytes) -> npt.NDArray[np.uint8]:
    magic, width, height, maxval, start = _pgm_header(raw)
    count = width * height
    if magic == b"P5":
        size = 2 if maxval > 255 else 1
        body = raw[start : start + count * size]
        if len(body) < count * size:
            msg = (
                f"the PGM image is cut short: {width} x {height} pixels need "
                f"{count * size} bytes, the file has {len(body)}"
            )
            raise ImageError(msg)
        values = np.frombuffer(body, dtype=">u2" if size == 2 else np.uint8).astype(np.int64)
    else:
        text = re.sub(rb"#[^\n\r]*", b" ", raw[start:])
        words = text.split()
        if len(words) < count:
            msg = (
                f"the PGM image is cut short: {width} x {height} pixels, the file has "
                f"{len(words)} values"
            )
            raise ImageError(msg)
        try:
            values = np.array([int(w) for w in words[:count]], dtype=np.int64)
        except ValueError:
            bad = next(w for w in words[:count] if not w.isdigit())
            msg = f"the plain PGM holds {bad.decode('latin-1')!r}, not a pixel value"
            raise ImageError(msg) from None
    if values.size and int(values.max()) > maxval:
        msg = f"a PGM pixel is {int(values.max())}, above the image's maxval {maxval}"
        raise ImageError(msg)
    if maxval != 255:
        values = values * 255 // maxval  # stretched to (or narrowed into) 0..255, as SDL does
    return values.astype(np.uint8).reshape(height, width, 1)


def _read_pillow(path: Path) -> MapImage:
    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(path) as img:
            img.load()
            return _from_pillow(img)
    except UnidentifiedImageError:
        msg = "not an image format Pillow can read (PGM, PNG, BMP, GIF, JPEG, TIFF… are)"
        raise ImageError(msg) from None
    except Image.DecompressionBombError as err:
        raise ImageError(str(err)) from None
    except (OSError, SyntaxError, ValueError) as err:  # Pillow's errors for broken files
        msg = f"the image is broken: {err}"
        raise ImageError(msg) from None


def _from_pillow(img: object) -> MapImage:
    from PIL import Image

    assert isinstance(img, Image.Image)
    mode = img.mode
    if mode == "P" and "transparency" in img.info:
        img, mode = img.convert("RGBA"), "RGBA"
    if mode in ("L", "P"):
        return MapImage(np.asarray(img, dtype=np.uint8)[..., None], has_alpha=False)
    if mode == "1":
        return MapImage(np.asarray(img.convert("L"), dtype=np.uint8)[..., None], has_alpha=False)
    if mode.startswith("I"):
        wide = np.asarray(img).astype(np.int64)
        return MapImage((np.clip(wide, 0, 65535) >> 8).astype(np.uint8)[..., None], False)
    if mode == "LA":
        grey, alpha = (np.asarray(band, dtype=np.uint8) for band in img.split())
        return MapImage(np.stack([grey, grey, grey, alpha], axis=-1), has_alpha=True)
    if mode == "RGB":
        return MapImage(np.asarray(img, dtype=np.uint8), has_alpha=False)
    if mode in ("RGBA", "RGBa", "La", "PA"):
        return MapImage(np.asarray(img.convert("RGBA"), dtype=np.uint8), has_alpha=True)
    if mode == "F":
        return MapImage(np.asarray(img.convert("L"), dtype=np.uint8)[..., None], False)
    return MapImage(np.asarray(img.convert("RGB"), dtype=np.uint8), has_alpha=False)


def read_map_image(path: str | os.PathLike[str]) -> MapImage:
    """The image's pixels as map_server's loader sees them.

    Raises:
        ImageError: the file cannot be read or is not an image (the message says why).
        OSError: the file cannot be opened.
    """
    path = Path(path)
    with open(path, "rb") as f:
        head = f.read(2)
        if head in (b"P2", b"P5"):
            raw = head + f.read()
            return MapImage(_read_pgm(raw), has_alpha=False)
    image = _read_pillow(path)
    if image.pixels.shape[0] == 0 or image.pixels.shape[1] == 0:
        msg = "the image has no pixels"
        raise ImageError(msg)
    return image
