"""Maps from the internet: images too large to decode, headers with absurd numbers, files that
are not files — each one error naming the image, at the YAML's ``image:`` line."""

from __future__ import annotations

import os
import re
import struct
import zlib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from belvedere import bounded
from belvedere.maps import (
    MapError,
    MapImage,
    _image,
    _load,
    load_map,
    occupancy_from_pixels,
    read_map_image,
)

YAML = (
    "image: {image}\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
    "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
)


def png_header(width: int, height: int) -> bytes:
    """A PNG that declares ``width`` x ``height`` pixels and holds none: what Pillow's
    ``open`` reads (the header) is all there is, so only a reader that decodes fails."""

    def chunk(kind: bytes, data: bytes) -> bytes:
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    ihdr = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)  # 8-bit greyscale
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IEND", b"")


def _map(tmp_path: Path, image: str, content: bytes | None = None) -> Path:
    if content is not None:
        (tmp_path / image).write_bytes(content)
    path = tmp_path / "map.yaml"
    path.write_text(YAML.format(image=image))
    return path


def test_a_169_megapixel_png_is_refused_from_its_header(tmp_path: Path) -> None:
    path = _map(tmp_path, "big.png", png_header(13000, 13000))
    with pytest.raises(MapError) as caught:
        load_map(path)
    assert caught.value.describe() == (
        f"{path}:1:8: error: cannot read the map image '{tmp_path}/big.png': it is 13,000 x "
        "13,000 pixels (169,000,000), more than the 67,108,864 (8192 x 8192) belvedere decodes"
    )


def test_a_png_past_pillows_own_limit_is_refused_with_belvederes_cap(tmp_path: Path) -> None:
    path = _map(tmp_path, "huge.png", png_header(20000, 20000))
    with pytest.raises(
        MapError, match=r"map\.yaml:1:8: .*it is 400,000,000 pixels, more than the 67,108,864"
    ):
        load_map(path)


def test_a_real_one_colour_png_past_the_cap(tmp_path: Path) -> None:
    from PIL import Image

    # 9000 x 8000 of one colour is 72 Mpx, a few hundred KiB as PNG (made in 10 strips)
    rows = zlib.compress(b"".join(b"\0" + b"\xff" * 9000 for _ in range(8000)), 9)
    data = png_header(9000, 8000)
    ihdr_end = data.index(b"IEND") - 4
    body = b"IDAT" + rows
    idat = struct.pack(">I", len(rows)) + body + struct.pack(">I", zlib.crc32(body))
    (tmp_path / "wide.png").write_bytes(data[:ihdr_end] + idat + data[ihdr_end:])
    with Image.open(tmp_path / "wide.png") as img:
        assert img.size == (9000, 8000)
    with pytest.raises(MapError, match=r"it is 9,000 x 8,000 pixels \(72,000,000\)"):
        load_map(_map(tmp_path, "wide.png"))


def test_the_cap_is_inclusive(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(bounded, "IMAGE_PIXELS", 100)
    ok = b"P5\n10 10\n255\n" + bytes(100)
    assert read_map_image(_write(tmp_path / "ok.pgm", ok)).pixels.shape == (10, 10, 1)
    with pytest.raises(_image.ImageError, match=r"it is 11 x 10 pixels \(110\), more than the 100"):
        read_map_image(_write(tmp_path / "no.pgm", b"P5\n11 10\n255\n" + bytes(110)))
    from PIL import Image

    Image.new("L", (11, 10)).save(tmp_path / "no.png")
    with pytest.raises(_image.ImageError, match=r"it is 11 x 10 pixels"):
        read_map_image(tmp_path / "no.png")


def _write(path: Path, content: bytes) -> Path:
    path.write_bytes(content)
    return path


@pytest.mark.parametrize(
    ("content", "error"),
    [
        (
            b"P5\n" + b"9" * 5000 + b" 1\n255\n\0",
            r"the PGM header's width is 5,000 digits long \(9999999999…\): more than any image",
        ),
        (b"P2\n1 " + b"7" * 20 + b"\n255\n0\n", r"the PGM header's height is 20 digits long"),
        (b"P5\n1 1\n" + b"1" * 4400 + b"\n\0", r"the PGM header's maxval is 4,400 digits long"),
        (b"P5\n100000 100000\n255\n", r"it is 100,000 x 100,000 pixels \(10,000,000,000\)"),
        (b"P2\n2 1\n255\n0 " + b"9" * 5000 + b"\n", r"a PGM pixel is 99999999999999999999…"),
        (b"P2\n2 1\n255\n0 -5\n", r"the plain PGM holds '-5', not a pixel value"),
        (b"P2\n2 1\n255\n0\n", r"cut short: 2 x 1 pixels, the file has 1 values"),
    ],
)
def test_absurd_pgm_headers_and_values_are_one_error(
    tmp_path: Path, content: bytes, error: str
) -> None:
    with pytest.raises(
        MapError, match=r"map\.yaml:1:8: error: cannot read the map image .*" + error
    ):
        load_map(_map(tmp_path, "m.pgm", content))


@pytest.mark.parametrize(
    ("image", "kind"),
    [
        ("fifo.pgm", "a FIFO \\(named pipe\\)"),
        ("/dev/zero", "a character device"),
        (".", "a directory"),
    ],
)
def test_a_map_image_that_is_not_a_regular_file_is_refused_unread(
    tmp_path: Path, image: str, kind: str
) -> None:
    os.mkfifo(tmp_path / "fifo.pgm")
    with pytest.raises(MapError, match=rf"map\.yaml:1:8: error: cannot read .*: it is {kind}, not"):
        load_map(_map(tmp_path, image))


def test_a_map_yaml_that_is_a_fifo_is_refused_unread(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "map.yaml")
    with pytest.raises(MapError, match=r"cannot read the map file '.*map\.yaml': it is a FIFO"):
        load_map(tmp_path / "map.yaml")


def test_a_map_yaml_that_is_not_utf8_is_refused_at_its_byte(tmp_path: Path) -> None:
    (tmp_path / "map.yaml").write_bytes(b"image: m.pgm\nresolution: 0.\xff\n")
    with pytest.raises(MapError, match=r"map\.yaml:2:15: error: .*not UTF-8 text \(byte 0xff\)"):
        load_map(tmp_path / "map.yaml")


def _plain_reference(raw: bytes) -> list[int]:
    """A plain PGM's values, read the simple way (the whole raster split at once)."""
    _, width, height, _, start = _image._pgm_header(raw)
    text = re.sub(rb"#[^\n\r]*", b" ", raw[start:])
    return [int(w) for w in text.split()[: width * height]]


raster_piece = st.one_of(
    st.integers(0, 255).map(lambda v: str(v).encode()),
    st.sampled_from([b" ", b"\n", b"\r\n", b"\t", b"  ", b"#c\n", b"# 9 9 9\r", b"#\n"]),
)


@settings(max_examples=150, derandomize=True, database=None)
@given(st.lists(raster_piece, max_size=120), st.integers(4, 40))
def test_the_plain_pgm_read_a_chunk_at_a_time_is_the_whole_read(
    pieces: list[bytes], chunk: int
) -> None:
    raster = b" ".join(p for p in pieces)  # values never run together
    count = len(re.sub(rb"#[^\n\r]*", b" ", raster).split())
    if count == 0:
        return
    raw = b"P2\n%d 1\n255\n" % count + raster
    expected = _plain_reference(raw)
    old = _image._CHUNK
    _image._CHUNK = chunk  # (not monkeypatch: hypothesis runs many examples per fixture)
    try:
        got = _image._read_pgm(raw)
    finally:
        _image._CHUNK = old
    assert got.reshape(-1).tolist() == expected


@pytest.mark.parametrize("mode", ["trinary", "scale", "raw"])
@pytest.mark.parametrize("channels", [1, 3, 4])
def test_occupancy_a_block_of_rows_at_a_time_is_the_whole_image_at_once(
    mode: _load.MapMode, channels: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    rng = np.random.default_rng(7)
    pixels = rng.integers(0, 256, size=(37, 23, channels), dtype=np.uint8)
    image = MapImage(pixels, has_alpha=channels == 4)
    options = {"negate": False, "occupied_thresh": 0.65, "free_thresh": 0.196, "mode": mode}
    whole = occupancy_from_pixels(image, **options)  # type: ignore[arg-type]
    monkeypatch.setattr(_load, "_BLOCK_CELLS", 50)  # two rows a block, the last one short
    blocks = occupancy_from_pixels(image, **options)  # type: ignore[arg-type]
    assert blocks.tolist() == whole.tolist()
    assert blocks.tolist()[0] == whole[0].tolist()  # row 0 is the image's bottom row


def test_a_number_too_large_for_a_double_is_an_error_at_its_place(tmp_path: Path) -> None:
    (tmp_path / "m.pgm").write_bytes(b"P5\n1 1\n255\n\0")
    path = _map(tmp_path, "m.pgm")
    path.write_text(path.read_text().replace("[0.0, 0.0, 0.0]", f"[0.0, {'9' * 400}, 0.0]"))
    with pytest.raises(MapError, match=r"map\.yaml:3:15: error: origin must be \[x, y, yaw\]"):
        load_map(path)
