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
other format goes through Pillow. Either way the image's size is checked from its header
against :data:`~belvedere.bounded.IMAGE_PIXELS` before any pixel is decoded.
"""

from __future__ import annotations

import math
import os
import re
import warnings
from dataclasses import dataclass
from typing import IO

import numpy as np
import numpy.typing as npt

from belvedere.bounded import IMAGE_FILE_BYTES, IMAGE_PIXELS, LimitError, check_pixels, open_regular

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

_DIGITS = re.compile(rb"\d+")
_MOST_DIGITS = 9
"""A header number with more digits is no size belvedere reads (and would cost Python's
``int`` quadratic time): refused as such before it is converted."""

_CHUNK = 1 << 20
"""Bytes of a plain PGM's raster read at a time (a few hundred thousand values)."""

_COMMENT = re.compile(rb"#[^\n\r]*")
_LINE_END = re.compile(rb"[\n\r]")
_DIGITS_AND_SPACE = b"0123456789 \t\n\r\v\f"


def _pgm_header(raw: bytes) -> tuple[bytes, int, int, int, int]:
    """(magic, width, height, maxval, offset of the raster)."""
    magic = raw[:2]
    pos = 2
    values: list[int] = []
    names = ("width", "height", "maxval")
    for name in names:
        skip = _TOKEN.match(raw, pos)
        pos = skip.end() if skip else pos
        digits = _DIGITS.match(raw, pos)
        if digits is None:
            if pos >= len(raw):
                msg = f"the PGM header ends before its {name}"
            else:
                found = raw[pos : pos + 10].decode("latin-1")
                msg = f"the PGM header's {name} is not a number (found {found!r})"
            raise ImageError(msg)
        if digits.end() - pos > _MOST_DIGITS:
            msg = (
                f"the PGM header's {name} is {digits.end() - pos:,} digits long "
                f"({raw[pos : pos + 10].decode('latin-1')}…): more than any image belvedere reads"
            )
            raise ImageError(msg)
        values.append(int(digits.group()))
        pos = digits.end()
        if name == "height":
            if values[0] <= 0 or values[1] <= 0:
                msg = f"the PGM image is {values[0]} x {values[1]} pixels: a map needs at least one"
                raise ImageError(msg)
            _check_pixels(values[0], values[1])
    width, height, maxval = values
    if not 0 < maxval < 65536:
        msg = f"the PGM maxval is {maxval}: it must be 1 to 65535"
        raise ImageError(msg)
    if pos >= len(raw) or raw[pos : pos + 1] not in (b" ", b"\t", b"\n", b"\r", b"\f", b"\v"):
        msg = "the PGM header does not end with a whitespace after its maxval"
        raise ImageError(msg)
    return magic, width, height, maxval, pos + 1


def _check_pixels(width: int, height: int) -> None:
    """A size of more pixels than belvedere decodes is an ImageError."""
    try:
        check_pixels(width, height, what="it")
    except LimitError as err:
        raise ImageError(err.message) from None


def _read_pgm(raw: bytes) -> npt.NDArray[np.uint8]:
    magic, width, height, maxval, start = _pgm_header(raw)
    count = width * height
    values: npt.NDArray[np.uint8] | npt.NDArray[np.uint16]
    if magic == b"P5":
        size = 2 if maxval > 255 else 1
        body = raw[start : start + count * size]
        if len(body) < count * size:
            msg = (
                f"the PGM image is cut short: {width} x {height} pixels need "
                f"{count * size} bytes, the file has {len(body)}"
            )
            raise ImageError(msg)
        values = np.frombuffer(body, dtype=">u2" if size == 2 else np.uint8)
        if maxval < (255 if size == 1 else 65535) and values.size:
            top = int(values.max())
            if top > maxval:
                msg = f"a PGM pixel is {top}, above the image's maxval {maxval}"
                raise ImageError(msg)
    else:
        values = _plain_values(raw, start, count, width, height, maxval)
    if maxval != 255 or values.dtype != np.uint8:
        # stretched to (or narrowed into) 0..255, as SDL does: v * 255 // maxval, looked up
        table = (np.arange(maxval + 1, dtype=np.int64) * 255 // maxval).astype(np.uint8)
        values = table[values]
    return np.asarray(values, dtype=np.uint8).reshape(height, width, 1)


def _plain_values(
    raw: bytes, pos: int, count: int, width: int, height: int, maxval: int
) -> npt.NDArray[np.uint16]:
    """The first ``count`` values of a plain PGM's raster from ``pos``, read a chunk at a
    time (never a Python object per pixel for the whole image); ``#`` comments are skipped
    wherever they are, as SDL_image skips them."""
    values = np.empty(count, dtype=np.uint16)
    filled = 0
    end_of_file = len(raw)
    while filled < count and pos < end_of_file:
        window = raw[pos : pos + _CHUNK]
        resume = pos + len(window)
        if resume < end_of_file:
            cut = max(window.rfind(b"\n"), window.rfind(b"\r"))
            if cut >= 0:  # whole lines: every comment in them ends in them
                window = window[: cut + 1]
                resume = pos + cut + 1
            elif (hash_at := window.find(b"#")) >= 0:  # the line goes on as a comment
                window = window[:hash_at]
                line_end = _LINE_END.search(raw, pos + hash_at)
                resume = line_end.end() if line_end else end_of_file
            else:  # one long line of values: up to its last whitespace
                cut = max(window.rfind(c) for c in (b" ", b"\t", b"\f", b"\v"))
                if cut < 0:
                    msg = f"the plain PGM holds a value of more than {_CHUNK:,} characters"
                    raise ImageError(msg)
                window = window[: cut + 1]
                resume = pos + cut + 1
        numbers = _words_to_values(window, count - filled, maxval)
        values[filled : filled + len(numbers)] = numbers
        filled += len(numbers)
        pos = resume
    if filled < count:
        msg = f"the PGM image is cut short: {width} x {height} pixels, the file has {filled} values"
        raise ImageError(msg)
    return values


def _words_to_values(window: bytes, most: int, maxval: int) -> npt.NDArray[np.int64]:
    """The first ``most`` pixel values in ``window`` (a plain PGM's raster, whole tokens),
    each checked to be digits only and at most ``maxval``."""
    cleaned = _COMMENT.sub(b" ", window)
    if cleaned.translate(None, _DIGITS_AND_SPACE):  # anything but digits and whitespace
        bad = next(w for w in cleaned.split() if not w.isdigit())
        msg = f"the plain PGM holds {bad[:20].decode('latin-1')!r}, not a pixel value"
        raise ImageError(msg)
    words = cleaned.split()[:most]
    if not words:
        return np.empty(0, dtype=np.int64)
    longest = max(words, key=len)
    if len(longest) > _MOST_DIGITS:  # above any maxval (and kept from numpy's fixed width)
        msg = f"a PGM pixel is {longest[:20].decode('latin-1')}…, above the image's maxval {maxval}"
        raise ImageError(msg)
    numbers = np.array(words).astype(np.int64)
    top = int(numbers.max())
    if top > maxval:
        msg = f"a PGM pixel is {top}, above the image's maxval {maxval}"
        raise ImageError(msg)
    return numbers


def _read_pillow(file: IO[bytes]) -> MapImage:
    from PIL import Image, UnidentifiedImageError

    try:
        with warnings.catch_warnings():
            # the size is checked against belvedere's own cap, below Pillow's warning's
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            img = Image.open(file)
        with img:
            _check_pixels(*img.size)  # from the header, before anything is decoded
            img.load()
            return _from_pillow(img)
    except UnidentifiedImageError:
        msg = "not an image format Pillow can read (PGM, PNG, BMP, GIF, JPEG, TIFF… are)"
        raise ImageError(msg) from None
    except Image.DecompressionBombError as err:
        found = re.search(r"\((\d+) pixels\)", str(err))
        side = math.isqrt(IMAGE_PIXELS)
        size = f"{int(found.group(1)):,} pixels" if found else "more pixels than that"
        msg = f"it is {size}, more than the {IMAGE_PIXELS:,} ({side} x {side}) belvedere decodes"
        raise ImageError(msg) from None
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
        wide = np.clip(np.asarray(img), 0, 65535)
        return MapImage((wide >> 8).astype(np.uint8)[..., None], False)
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

    Only a regular file of at most :data:`~belvedere.bounded.IMAGE_FILE_BYTES` is read, and
    only an image of at most :data:`~belvedere.bounded.IMAGE_PIXELS` pixels (its size read
    from its header) is decoded.

    Raises:
        LimitError: the file cannot be opened or is not a regular file of a sane size
            (``cannot read the map image 'map.pgm': it is a FIFO…``).
        ImageError: the file is not an image, is broken, or has too many pixels (the message
            says why).
        OSError: the file cannot be read.
    """
    shown = repr(os.fspath(path))
    with open_regular(path, limit=IMAGE_FILE_BYTES, what="the map image", name=shown) as f:
        head = f.read(2)
        if head in (b"P2", b"P5"):
            raw = head + f.read()
            return MapImage(_read_pgm(raw), has_alpha=False)
        f.seek(0)
        image = _read_pillow(f)
    if image.pixels.shape[0] == 0 or image.pixels.shape[1] == 0:
        msg = "the image has no pixels"
        raise ImageError(msg)
    return image
