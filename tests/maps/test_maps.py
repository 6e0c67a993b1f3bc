"""Map files as map_server reads them and map_saver writes them: formats, values, round trips
and the errors bad files give."""

from __future__ import annotations

import os
import re
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from PIL import Image

from belvedere.maps import (
    MapError,
    MapImage,
    OccupancyMap,
    grid_message,
    load_image_map,
    load_map,
    map_from_message,
    map_pgm_bytes,
    map_yaml_text,
    occupancy_from_pixels,
    quat_xyzw_from_yaw,
    read_map_image,
    read_map_yaml,
    save_map,
    yaw_from_quat_xyzw,
)
from tests.maps.reference import loader_cells, saver_pixels

SAVER_YAML = (
    "image: {image}\nresolution: {res}\norigin: [{x}, {y}, {yaw}]\nnegate: 0\n"
    "occupied_thresh: 0.65\nfree_thresh: 0.196\n\n"
)


def _pgm(width: int, height: int, raster: bytes, comment: str = "") -> bytes:
    head = f"P5\n{comment}{width} {height}\n255\n".encode()
    return head + raster


def _cloister(width: int = 320, height: int = 240) -> np.ndarray:
    """A cloister-like map as gmapping leaves one: unknown outside, a walled courtyard of
    free cells, pillars (occupied) around it, a few grey scan fringes."""
    cells = np.full((height, width), -1, dtype=np.int8)
    cells[20:-20, 30:-30] = 0
    cells[20:22, 30:-30] = cells[-22:-20, 30:-30] = 100
    cells[20:-20, 30:32] = cells[20:-20, -32:-30] = 100
    for cx in range(60, width - 60, 40):
        for cy in (60, height - 60):
            cells[cy - 3 : cy + 3, cx - 3 : cx + 3] = 100
    rng = np.random.default_rng(7)
    fringe = rng.random(cells.shape) < 0.01
    cells[fringe] = rng.integers(1, 99, size=int(fringe.sum()))
    return cells


# --- writing: map_saver's bytes --------------------------------------------------------------
def test_the_saved_files_are_map_savers_bytes(tmp_path: Path) -> None:
    cells = np.array([[0, 100, -1, 25, 26], [64, 65, 99, -128, 127]], dtype=np.int8)
    grid = OccupancyMap(cells, 0.05, (-15.4, -12.2, 0.0))
    pgm, yaml_file = save_map(tmp_path / "cloister_gmapping", grid)
    # the image's top row is the grid's last row; 0..25 free, 65.. occupied, else unknown
    assert pgm.read_bytes() == (
        b"P5\n# CREATOR: map_saver.cpp 0.050 m/pix\n5 2\n255\n"
        + bytes([205, 0, 0, 205, 0])
        + bytes([254, 0, 205, 254, 205])
    )
    assert yaml_file.read_text() == SAVER_YAML.format(
        image=f"{tmp_path}/cloister_gmapping.pgm",
        res="0.050000",
        x="-15.400000",
        y="-12.200000",
        yaw="0.000000",
    )


def test_saver_thresholds_are_percentages_as_occ_and_free() -> None:
    cells = np.arange(-128, 128, dtype=np.int16).astype(np.int8).reshape(16, 16)
    grid = OccupancyMap(cells, 0.1)
    for occupied, free in ((65, 25), (90, 10), (1, 0), (100, 99)):
        raster = map_pgm_bytes(grid, occupied=occupied, free=free).split(b"\n255\n", 1)[1]
        expected = saver_pixels([int(v) for v in cells.reshape(-1)], 16, 16, occupied, free)
        assert raster == expected


def test_the_yaml_keeps_map_savers_number_formatting() -> None:
    grid = OccupancyMap(np.zeros((1, 1), np.int8), 0.025, (1e-7, -123456.5, -1.5707963))
    assert map_yaml_text(grid, "m.pgm") == SAVER_YAML.format(
        image="m.pgm", res="0.025000", x="0.000000", y="-123456.500000", yaw="-1.570796"
    )
    # the resolution travels as a float32 and the yaw as a quaternion, as in the message
    odd = OccupancyMap(np.zeros((1, 1), np.int8), 0.0123456789, (0.0, 0.0, 3.0))
    text = map_yaml_text(odd, "m.pgm")
    assert "resolution: 0.012346\n" in text
    assert "origin: [0.000000, 0.000000, 3.000000]\n" in text


def test_yaw_goes_through_the_quaternion_as_tf2_does() -> None:
    for yaw in (0.0, 0.3, -2.5, 3.14159, -3.14159):
        assert yaw_from_quat_xyzw(quat_xyzw_from_yaw(yaw)) == pytest.approx(yaw, abs=1e-12)
    # beyond pi the saved yaw wraps, as map_saver's does
    assert yaw_from_quat_xyzw(quat_xyzw_from_yaw(4.0)) == pytest.approx(4.0 - 2 * np.pi)
    assert yaw_from_quat_xyzw((0.0, 0.0, 0.0, 0.0)) == 0.0  # a message's default
    assert quat_xyzw_from_yaw(0.0) == (0.0, 0.0, 0.0, 1.0)


def test_saving_is_atomic_and_names_the_file(tmp_path: Path) -> None:
    from belvedere.fileio import FileWriteError

    grid = OccupancyMap(np.zeros((2, 2), np.int8), 0.05)
    old = save_map(tmp_path / "m", grid)[0].read_bytes()
    blocker = tmp_path / "m.yaml"
    blocker.unlink()
    blocker.mkdir()  # the YAML cannot be written: neither file changes
    with pytest.raises(FileWriteError, match=r"m\.yaml: Is a directory"):
        save_map(tmp_path / "m", OccupancyMap(np.full((3, 3), 100, np.int8), 0.05))
    assert (tmp_path / "m.pgm").read_bytes() == old
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.pgm", "m.yaml"]


# --- round trips -----------------------------------------------------------------------------
def _round_trip(grid: OccupancyMap, name: str = "map") -> tuple[bytes, str, OccupancyMap]:
    """Save as ``map_saver -f name`` in one directory, load, save in another: the second
    save's bytes must equal the first's."""
    with tempfile.TemporaryDirectory() as first, tempfile.TemporaryDirectory() as second:
        cwd = os.getcwd()
        try:
            os.chdir(first)
            save_map(name, grid)
            pgm, text = Path(f"{name}.pgm").read_bytes(), Path(f"{name}.yaml").read_text()
            loaded = load_map(f"{first}/{name}.yaml")
            os.chdir(second)
            save_map(name, loaded)
            assert Path(f"{name}.pgm").read_bytes() == pgm
            assert Path(f"{name}.yaml").read_text() == text
        finally:
            os.chdir(cwd)
    return pgm, text, loaded


@given(
    cells=hnp.arrays(np.int8, hnp.array_shapes(min_dims=2, max_dims=2, max_side=40)),
    resolution=st.floats(0.001, 5.0),
    x=st.floats(-1000, 1000),
    y=st.floats(-1000, 1000),
    yaw=st.floats(-3.14159, 3.14159).filter(lambda a: not -5e-7 < a < 0),
)
def test_saved_maps_load_and_save_byte_identical(
    cells: np.ndarray, resolution: float, x: float, y: float, yaw: float
) -> None:
    """(Two yaws change on the way, in ROS as here: one written ``-0.000000`` comes back as
    0 through the quaternion, and one beyond pi wraps; the strategy leaves them out.)"""
    grid = OccupancyMap(cells, resolution, (x, y, yaw))
    _, _, loaded = _round_trip(grid)
    # what survives is map_saver's three classes
    expected = np.where((cells >= 0) & (cells <= 25), 0, np.where(cells >= 65, 100, -1))
    assert np.array_equal(loaded.data, expected)


def test_a_cloister_like_map_round_trips() -> None:
    grid = OccupancyMap(_cloister(), 0.05, (-15.4, -12.2, 0.0))
    pgm, text, loaded = _round_trip(grid, "cloister_gmapping")
    assert pgm.startswith(b"P5\n# CREATOR: map_saver.cpp 0.050 m/pix\n320 240\n255\n")
    assert text.startswith("image: cloister_gmapping.pgm\nresolution: 0.050000\n")
    assert loaded.origin == (-15.4, -12.2, 0.0)
    assert loaded.data[20, 100] == 100
    assert loaded.data[100, 100] == 0
    assert loaded.data[0, 0] == -1


def test_a_blank_map_from_an_image_editor_loads_and_round_trips(tmp_path: Path) -> None:
    """The course's blank map: 0.01 m, white (255) everywhere, GIMP's comment, keys in
    another order, a comment after a value, no trailing blank line."""
    (tmp_path / "blank_map.pgm").write_bytes(
        _pgm(500, 400, bytes([255]) * 200_000, "# CREATOR: GIMP PNM Filter Version 1.1\n")
    )
    (tmp_path / "blank_map.yaml").write_text(
        "image: blank_map.pgm\nresolution: 0.01\norigin: [-2.5, -2.0, 0]\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196 # from the Willow Garage map\nnegate: 0\n"
    )
    grid = load_map(tmp_path / "blank_map.yaml")
    assert (grid.width, grid.height, grid.resolution) == (500, 400, 0.01)
    assert not grid.data.any()  # all free
    pgm, text, _ = _round_trip(grid, "blank_map")
    assert pgm == _pgm(500, 400, bytes([254]) * 200_000, "# CREATOR: map_saver.cpp 0.010 m/pix\n")
    assert text == SAVER_YAML.format(
        image="blank_map.pgm", res="0.010000", x="-2.500000", y="-2.000000", yaw="0.000000"
    )


def test_a_plain_pgm_reads_as_its_raw_twin(tmp_path: Path) -> None:
    values = [0, 254, 205, 128, 255, 1, 100, 64, 200, 30, 0, 254]
    plain = "P2\n# test_map, saved as ASCII\n4 3\n255\n" + "\n".join(
        " ".join(str(v) for v in values[r * 4 : r * 4 + 4]) for r in range(3)
    )
    (tmp_path / "plain.pgm").write_text(plain + "\n")
    (tmp_path / "raw.pgm").write_bytes(_pgm(4, 3, bytes(values)))
    a = read_map_image(tmp_path / "plain.pgm")
    b = read_map_image(tmp_path / "raw.pgm")
    assert np.array_equal(a.pixels, b.pixels)
    assert a.pixels[:, :, 0].tolist() == [values[0:4], values[4:8], values[8:12]]
    # a maxval below 255 is stretched as SDL_image does
    (tmp_path / "dim.pgm").write_text("P2 3 1 100 0 50 100\n")
    assert read_map_image(tmp_path / "dim.pgm").pixels.reshape(-1).tolist() == [0, 127, 255]


# --- reading: the occupancy map_server computes ----------------------------------------------
@st.composite
def _images(draw: st.DrawFn) -> MapImage:
    channels, alpha = draw(st.sampled_from([(1, False), (3, False), (4, True), (4, False)]))
    shape = (draw(st.integers(1, 6)), draw(st.integers(1, 6)), channels)
    return MapImage(draw(hnp.arrays(np.uint8, shape)), has_alpha=alpha)


@given(
    image=_images(),
    negate=st.booleans(),
    occ=st.floats(0.0, 1.0),
    free=st.floats(0.0, 1.0),
    mode=st.sampled_from(["trinary", "scale", "raw"]),
)
def test_cells_are_what_map_servers_loop_computes(
    image: MapImage, negate: bool, occ: float, free: float, mode: str
) -> None:
    if mode == "scale" and occ <= free:
        free, occ = sorted((occ, free))
        if occ == free:
            return  # map_server divides by zero there
    cells = occupancy_from_pixels(
        image,
        negate=negate,
        occupied_thresh=occ,
        free_thresh=free,
        mode=mode,  # type: ignore[arg-type]
    )
    expected = loader_cells(
        image.pixels, image.has_alpha, negate=negate, occ_th=occ, free_th=free, mode=mode
    )
    assert cells.reshape(-1).tolist() == expected


def test_trinary_scale_and_raw_on_one_row(tmp_path: Path) -> None:
    row = bytes([0, 50, 100, 150, 205, 230, 254, 255])
    (tmp_path / "row.pgm").write_bytes(_pgm(8, 1, row))

    def cells(mode: str, negate: bool = False) -> list[int]:
        grid = load_image_map(tmp_path / "row.pgm", 0.1, mode=mode, negate=negate)  # type: ignore[arg-type]
        return grid.data.reshape(-1).tolist()

    # p = (255 - v) / 255: occupied above 0.65, free below 0.196 (205 is just above: unknown)
    assert cells("trinary") == [100, 100, -1, -1, -1, 0, 0, 0]
    assert cells("scale") == [100, 100, 89, 47, 1, 0, 0, 0]
    assert cells("raw") == [0, 50, 100, -106, -51, -26, -2, -1]  # int8 wraps, as in the message
    assert cells("trinary", negate=True) == [0, -1, -1, -1, 100, 100, 100, 100]


def test_colour_images_are_averaged_as_sdl_hands_them_over(tmp_path: Path) -> None:
    # RGB: the mean of the three bytes (pure red is dark: 85)
    rgb = np.array([[[255, 0, 0], [255, 255, 0], [254, 254, 254]]], np.uint8)
    Image.fromarray(rgb).save(tmp_path / "rgb.png")
    assert load_image_map(tmp_path / "rgb.png", 0.1).data.tolist() == [[100, -1, 0]]
    # RGBA: trinary averages alpha in; scale leaves it out and makes alpha 0 unknown
    rgba = np.array([[[254, 254, 254, 0], [150, 150, 150, 255], [150, 150, 150, 0]]], np.uint8)
    Image.fromarray(rgba).save(tmp_path / "rgba.png")
    assert load_image_map(tmp_path / "rgba.png", 0.1).data.tolist() == [[-1, -1, -1]]
    assert load_image_map(tmp_path / "rgba.png", 0.1, mode="scale").data.tolist() == [[0, 47, -1]]
    # a palette image gives SDL its indices, not its colours
    pal = Image.new("P", (2, 1))
    pal.putpalette([255, 255, 255, 0, 0, 0] + [0] * 762)
    pal.putdata([0, 1])
    pal.save(tmp_path / "pal.png")
    assert read_map_image(tmp_path / "pal.png").pixels.reshape(-1).tolist() == [0, 1]
    # grey + alpha becomes RGBA; 16-bit grey keeps its high byte
    Image.fromarray(np.array([[[10, 200]]], np.uint8), mode="LA").save(tmp_path / "la.png")
    assert read_map_image(tmp_path / "la.png").pixels.reshape(-1).tolist() == [10, 10, 10, 200]
    Image.fromarray(np.array([[0x1234, 0xFFFF]], np.uint16)).save(tmp_path / "wide.png")
    assert read_map_image(tmp_path / "wide.png").pixels.reshape(-1).tolist() == [0x12, 0xFF]


def test_the_image_top_row_is_the_grid_last_row(tmp_path: Path) -> None:
    (tmp_path / "m.pgm").write_bytes(_pgm(2, 2, bytes([0, 0, 254, 254])))
    (tmp_path / "m.yaml").write_text(
        "image: m.pgm\nresolution: 0.5\norigin: [1, 2, 0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\nmode: trinary\n"
    )
    grid = load_map(tmp_path / "m.yaml")
    assert grid.data.tolist() == [[0, 0], [100, 100]]
    msg = grid_message(grid, frame_id="world", stamp_ns=3_000_000_001)
    assert msg.data.tolist() == [0, 0, 100, 100]
    assert (msg.header.frame_id, msg.header.stamp.sec, msg.header.stamp.nanosec) == ("world", 3, 1)
    assert (msg.info.width, msg.info.height, msg.info.origin.position.x) == (2, 2, 1.0)
    again = map_from_message(msg)
    assert again.data.tolist() == grid.data.tolist()
    assert again.origin == (1.0, 2.0, 0.0)


def test_an_absolute_image_path_and_numbers_written_as_strings(tmp_path: Path) -> None:
    (tmp_path / "007.pgm").write_bytes(_pgm(1, 1, bytes([0])))
    other = tmp_path / "elsewhere"
    other.mkdir()
    (other / "m.yaml").write_text(
        f"image: {tmp_path}/007.pgm\nresolution: 5e-2\norigin: [0, 0, 0]\nnegate: 1\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    meta = read_map_yaml(other / "m.yaml")
    assert (meta.image, meta.resolution, meta.negate) == (tmp_path / "007.pgm", 0.05, True)
    assert load_map(other / "m.yaml").data.tolist() == [[0]]  # negated black is free


# --- errors ----------------------------------------------------------------------------------
GOOD = (
    "image: m.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
    "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
)


@pytest.mark.parametrize(
    ("change", "error"),
    [
        (("resolution: 0.05\n", ""), r"m\.yaml:1:1: error: the map has no 'resolution'"),
        (("negate: 0\n", ""), r"m\.yaml:1:1: error: the map has no 'negate' \(map_server needs"),
        (("resolution: 0.05", "resolution: fine"), r"m\.yaml:2:13: error: resolution must be a "
         r"positive number of metres per cell, got 'fine'"),
        (("resolution: 0.05", "resolution: 0"), r"m\.yaml:2:13: .*got 0"),
        (("negate: 0", "negate: maybe"), r"m\.yaml:4:9: error: negate must be 0 or 1, got 'maybe'"),
        (("free_thresh: 0.196", "free_thresh: [1]"), r"m\.yaml:6:14: error: free_thresh must be"),
        (("negate: 0\n", "negate: 0\nmode: ternary\n"),
         r"m\.yaml:5:7: error: mode must be trinary, scale or raw, got 'ternary'"),
        (("[0.0, 0.0, 0.0]", "[0.0, 0.0]"), r"m\.yaml:3:9: error: origin must be \[x, y, yaw\]"),
        (("[0.0, 0.0, 0.0]", "[0.0, north, 0.0]"), r"m\.yaml:3:15: error: origin must be"),
        (("image: m.pgm", "image: ''"), r"m\.yaml:1:8: error: image must name the map's image"),
        (("image: m.pgm", "image: gone.pgm"),
         r"m\.yaml:1:8: error: cannot read the map image '.*gone\.pgm': No such file"),
        (("origin:", "origin: [\norigin:"), r"m\.yaml:\d+:\d+: error: invalid YAML"),
        ((GOOD, "- image: m.pgm\n"), r"m\.yaml:1:1: error: a map's YAML is a mapping .* a list"),
        ((GOOD, ""), r"m\.yaml:1:1: error: a map's YAML is a mapping .* holds nothing"),
    ],
)  # fmt: skip
def test_a_bad_map_yaml_is_one_error_at_its_line(
    tmp_path: Path, change: tuple[str, str], error: str
) -> None:
    (tmp_path / "m.pgm").write_bytes(_pgm(1, 1, b"\0"))
    (tmp_path / "m.yaml").write_text(GOOD.replace(*change))
    with pytest.raises(MapError) as caught:
        load_map(tmp_path / "m.yaml")
    assert caught.value.describe().count("error:") == 1
    assert re.search(error, caught.value.describe()), caught.value.describe()


@pytest.mark.parametrize(
    ("content", "error"),
    [
        (
            b"P5\n2 2\n255\n\0\0",
            r"the PGM image is cut short: 2 x 2 pixels need 4 bytes, the file has 2",
        ),
        (b"P5\n2", r"the PGM header ends before its height"),
        (b"P5\nwide 2 255\n", r"the PGM header's width is not a number \(found 'wide 2 255'\)"),
        (b"P5\n0 2\n255\n", r"the PGM image is 0 x 2 pixels: a map needs at least one"),
        (b"P2\n2 1\n255\n0 300\n", r"a PGM pixel is 300, above the image's maxval 255"),
        (b"P2\n2 1\n255\n0 x\n", r"the plain PGM holds 'x', not a pixel value"),
        (b"GIF89a garbage", r"the image is broken|not an image format"),
        (b"hello", r"not an image format Pillow can read"),
    ],
)
def test_a_bad_image_is_one_error_naming_it(tmp_path: Path, content: bytes, error: str) -> None:
    (tmp_path / "m.pgm").write_bytes(content)
    (tmp_path / "m.yaml").write_text(GOOD)
    with pytest.raises(MapError, match=r"cannot read the map image '.*m\.pgm': " + error) as e:
        load_map(tmp_path / "m.yaml")
    assert str(e.value.location) == f"{tmp_path}/m.yaml:1:8"


def test_an_unreadable_yaml_is_an_error(tmp_path: Path) -> None:
    with pytest.raises(MapError, match=r"cannot read the map file '.*none\.yaml': No such file"):
        load_map(tmp_path / "none.yaml")
