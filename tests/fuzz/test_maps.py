"""Fuzzing the map reader: mutated map YAML, and mutated PGM and PNG images (their headers
most of all), give a map or belvedere's own error — nothing else escapes, nothing hangs, and
no map has more cells than the pixel cap allows."""

from __future__ import annotations

import contextlib
import io
import struct
import zlib
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from belvedere.bounded import IMAGE_PIXELS
from belvedere.errors import BelvedereError
from belvedere.maps import load_map
from tests.fuzz._mutate import (
    HOSTILE_NUMBERS,
    Mutation,
    fuzz_settings,
    mutations,
    run_bounded,
    text_mutant,
)

YAMLS = (
    "image: m.pgm\nresolution: 0.05\norigin: [-10.0, -10.0, 0.0]\nnegate: 0\n"
    "occupied_thresh: 0.65\nfree_thresh: 0.196\n",
    "image: m.png\nresolution: 0.1\norigin: [0.5, 2, 0.3]\nnegate: 1\n"
    "occupied_thresh: 0.9\nfree_thresh: 0.1\nmode: scale\n",
    "{image: m.pgm, resolution: 5e-2, origin: [0, 0, 0], negate: 0,\n"
    " occupied_thresh: 0.65, free_thresh: 0.196, mode: raw}\n",
)
YAML_TOKENS = (
    *HOSTILE_NUMBERS,
    ": ",
    "- ",
    "[",
    "]",
    "{",
    "}",
    "&a ",
    "*a",
    "!!binary ",
    "!degrees ",
    "\n",
    "image: /dev/zero\n",
    "image: .\n",
    "image: m.png\n",
    "image: m.pgm\n",
    "mode: scale\n",
    "mode: raw\n",
    "é",
    "\x00",
)
IMAGE_TOKENS = (
    "9" * 5000,
    "99999",
    "65536",
    "100000 100000",
    "0",
    "-1",
    "#",
    "# a comment\n",
    "\n",
    "\r",
    " ",
    "P2",
    "P5",
    "x",
    "\x00",
    "\xff" * 8,
)


def _pgm(kind: bytes, width: int, height: int, maxval: int) -> bytes:
    values = [(7 * i) % (maxval + 1) for i in range(width * height)]
    head = b"%s\n# made by the fuzzer\n%d %d\n%d\n" % (kind, width, height, maxval)
    if kind == b"P2":
        return head + " ".join(map(str, values)).encode() + b"\n"
    if maxval > 255:
        return head + b"".join(struct.pack(">H", v) for v in values)
    return head + bytes(values)


def _png(mode: str, width: int, height: int) -> bytes:
    from PIL import Image

    out = io.BytesIO()
    colour = 128 if mode in ("L", "P") else (10, 200, 30, 128)[: len(mode)]
    Image.new(mode, (width, height), colour).save(out, format="PNG")
    return out.getvalue()


IMAGES = {
    "p5": _pgm(b"P5", 7, 5, 255),
    "p5-16": _pgm(b"P5", 3, 4, 1000),
    "p2": _pgm(b"P2", 6, 3, 100),
    "png-l": _png("L", 5, 4),
    "png-rgba": _png("RGBA", 4, 3),
    "png-p": _png("P", 3, 3),
}


def _bytes_mutant(data: bytes, edits: list[Mutation]) -> bytes:
    """The text edits on bytes (each byte one latin-1 character), inserting IMAGE_TOKENS."""
    return text_mutant(data.decode("latin-1"), edits, IMAGE_TOKENS).encode("latin-1")


def _load(directory: Path, yaml_text: str, image_name: str, image: bytes) -> None:
    (directory / image_name).write_bytes(image)
    path = directory / "map.yaml"
    path.write_text(yaml_text, encoding="utf-8")
    with run_bounded(60), contextlib.suppress(BelvedereError):
        grid = load_map(path)
        assert grid.data.size <= IMAGE_PIXELS


@pytest.fixture(scope="module")
def workdir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("maps")


@fuzz_settings(150)
@given(st.sampled_from(YAMLS), mutations())
def test_map_yaml_mutants(workdir: Path, seed: str, edits: list[Mutation]) -> None:
    text = text_mutant(seed, edits, YAML_TOKENS)
    (workdir / "m.png").write_bytes(IMAGES["png-l"])
    _load(workdir, text, "m.pgm", IMAGES["p5"])


@fuzz_settings(250)
@given(st.sampled_from(sorted(IMAGES)), mutations(max_edits=4), st.booleans())
def test_map_image_mutants(
    workdir: Path, kind: str, edits: list[Mutation], header_only: bool
) -> None:
    image = IMAGES[kind]
    if header_only:  # aim the edits at the header, where the sizes are
        edits = [Mutation(e.kind, e.a % 24, e.b, e.c) for e in edits]
    name = "m.png" if kind.startswith("png") else "m.pgm"
    _load(workdir, YAMLS[0].replace("m.pgm", name), name, _bytes_mutant(image, edits))


def _png_chunk(kind: bytes, data: bytes) -> bytes:
    body = kind + data
    return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))


@fuzz_settings(100)
@given(
    st.integers(0, 2**31 - 1),
    st.integers(0, 2**31 - 1),
    st.sampled_from([(8, 0), (8, 2), (8, 3), (8, 4), (8, 6), (16, 0), (1, 0), (16, 6)]),
    st.binary(max_size=64),
)
def test_png_headers_of_any_size(
    workdir: Path, width: int, height: int, depth_colour: tuple[int, int], body: bytes
) -> None:
    depth, colour = depth_colour
    ihdr = struct.pack(">IIBBBBB", width, height, depth, colour, 0, 0, 0)
    png = (
        b"\x89PNG\r\n\x1a\n"
        + _png_chunk(b"IHDR", ihdr)
        + _png_chunk(b"IDAT", zlib.compress(body))
        + _png_chunk(b"IEND", b"")
    )
    _load(workdir, YAMLS[0].replace("m.pgm", "m.png"), "m.png", png)
