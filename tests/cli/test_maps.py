"""Maps end to end: ``rosrun map_server map_saver -f NAME`` against a launch that runs in
another process (the course's workflow), and ``belvedere map show``."""

from __future__ import annotations

import contextlib
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from belvedere.cli import main
from belvedere.graph import graph_running
from belvedere.maps import OccupancyMap, format_tum_line, save_map
from tests.waiting import DEADLINE, wait_until

BELVEDERE = [sys.executable, "-m", "belvedere"]


def _cloister() -> np.ndarray:
    cells = np.full((120, 160), -1, dtype=np.int8)
    cells[10:-10, 10:-10] = 0
    cells[10:12, 10:-10] = cells[-12:-10, 10:-10] = 100
    cells[10:-10, 10:12] = cells[10:-10, -12:-10] = 100
    cells[50:56, 60:66] = 100
    return cells


@pytest.fixture
def pkg(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """``maps_pkg`` with ``maps/cloister.yaml`` as ``map_saver -f cloister`` wrote it there."""
    root = tmp_path / "ws" / "maps_pkg"
    (root / "maps").mkdir(parents=True)
    (root / "launch").mkdir()
    (root / "package.xml").write_text("<package><name>maps_pkg</name></package>")
    monkeypatch.chdir(root / "maps")
    save_map("cloister", OccupancyMap(_cloister(), 0.05, (-4.0, -3.0, 0.0)))
    monkeypatch.chdir(tmp_path)
    return root


@contextlib.contextmanager
def _running(command: list[str]) -> Iterator[subprocess.Popen[bytes]]:
    """``command`` in the background until the graph it makes is up; stopped after."""
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        wait_until(
            lambda: graph_running() or process.poll() is not None,
            what=f"the graph of {' '.join(command[3:])}",
        )
        assert process.poll() is None, "the background command ended"
        yield process
    finally:
        process.terminate()
        process.wait(timeout=DEADLINE)


def _save_in(directory: Path, name: str) -> subprocess.CompletedProcess[str]:
    directory.mkdir(exist_ok=True)
    return subprocess.run(
        [*BELVEDERE, "run", "map_server", "map_saver", "-f", name],
        cwd=directory, capture_output=True, text=True, timeout=DEADLINE, check=False,
    )  # fmt: skip


def _same_files(pkg: Path, saved: Path) -> None:
    for suffix in (".pgm", ".yaml"):
        original = (pkg / "maps" / f"cloister{suffix}").read_bytes()
        assert (saved / f"cloister{suffix}").read_bytes() == original, suffix


def test_map_saver_saves_what_a_running_launch_serves(pkg: Path, tmp_path: Path) -> None:
    launch = pkg / "launch" / "map.launch"
    launch.write_text(
        '<launch>\n  <node pkg="map_server" type="map_server" name="map_server"'
        ' args="$(find maps_pkg)/maps/cloister.yaml"/>\n</launch>\n'
    )
    command = [*BELVEDERE, "launch", "--package-path", str(pkg.parent), "--headless", str(launch)]
    with _running(command):
        done = _save_in(tmp_path / "out", "cloister")
        assert done.returncode == 0, done.stderr
        # it joined the launch's graph (no second graph of its own) and ended by itself
        assert "connected" in done.stderr.splitlines()[0]
        # map_saver's log, as ROS prints it: on stdout, "[INFO] [time]: text"
        logged = [line.split("]: ", 1)[1] for line in done.stdout.splitlines()]
        assert logged[-4:] == [
            "Received a 160 X 120 map @ 0.050 m/pix",
            "Writing map occupancy data to cloister.pgm",
            "Writing map occupancy data to cloister.yaml",
            "Done",
        ]
    _same_files(pkg, tmp_path / "out")


def test_map_server_run_joins_a_running_simulation_too(pkg: Path, tmp_path: Path) -> None:
    """``rosrun map_server map_server`` while a launch runs joins its graph (and follows its
    clock); map_saver in a third process saves the map it serves."""
    launch = pkg / "launch" / "tf.launch"
    launch.write_text(
        '<launch>\n  <node pkg="tf2_ros" type="static_transform_publisher" name="stp"'
        ' args="0 0 0 0 0 0 map odom"/>\n</launch>\n'
    )
    base = [*BELVEDERE, "launch", "--package-path", str(pkg.parent), "--headless"]
    server = [*BELVEDERE, "run", "map_server", "map_server", str(pkg / "maps/cloister.yaml")]
    with (
        _running([*base, str(launch)]),
        subprocess.Popen(server, stderr=subprocess.PIPE, text=True) as served,
    ):
        try:
            assert served.stderr is not None
            first = served.stderr.readline()
            assert "connected" in first, first
            done = _save_in(tmp_path / "out", "cloister")
            assert done.returncode == 0, done.stderr
        finally:
            served.terminate()
    _same_files(pkg, tmp_path / "out")


def test_map_show_draws_the_map_and_a_trajectory(
    pkg: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    tum = tmp_path / "path.tum"
    tum.write_text(
        "# stamp x y z qx qy qz qw\n"
        + format_tum_line(0.0, (-1.5, -0.5, 0.0), (0, 0, 0, 1))
        + format_tum_line(1.0, (-1.0, 0.0, 0.0), (0, 0, 0, 1))
    )
    out = tmp_path / "map.png"
    yaml_file = str(pkg / "maps/cloister.yaml")
    assert main(["map", "show", yaml_file, "-o", str(out), "--trajectory", str(tum)]) == 0
    err = capsys.readouterr().err
    assert f"wrote {out} (480 x 360 px)" in err  # enlarged 3 times
    assert "160 x 120 cells @ 0.050 m" in err
    assert "2 poses drawn" in err
    picture = np.asarray(Image.open(out).convert("RGB"))
    assert picture.shape == (360, 480, 3)
    assert tuple(picture[0, 0]) == (205, 205, 205)  # unknown
    assert tuple(picture[360 - 3 * 30, 3 * 30]) == (254, 254, 254)  # free
    assert tuple(picture[360 - 3 * 53, 3 * 63]) == (0, 0, 0)  # the pillar
    # the trajectory ends at (-1, 0): cell (60, 60) from the origin (-4, -3), a red dot
    r, g, b = picture[360 - 3 * 60, 3 * 60]
    assert r > 200
    assert g < 60
    assert b < 60
    r, g, b = picture[360 - 3 * 50, 3 * 50]  # starts at (-1.5, -0.5): green
    assert g > 150
    assert r < 60


def test_map_show_errors(pkg: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    yaml_file = str(pkg / "maps/cloister.yaml")
    assert main(["map", "show", yaml_file, "-o", str(tmp_path / "x.jpg")]) == 1
    assert "the picture is a PNG" in capsys.readouterr().err
    bad = tmp_path / "bad.tum"
    bad.write_text("0 1 2 3\n")
    assert main(["map", "show", yaml_file, "--trajectory", str(bad), "-o", "m.png"]) == 1
    assert f"{bad}:1:1: error: a TUM line is 8 numbers" in capsys.readouterr().err
    assert main(["map", "show", str(tmp_path / "none.yaml")]) == 1
    assert "cannot read the map file" in capsys.readouterr().err


def test_map_show_writes_png_to_a_pipe(pkg: Path) -> None:
    done = subprocess.run(
        [*BELVEDERE, "map", "show", str(pkg / "maps/cloister.yaml")],
        capture_output=True, timeout=DEADLINE, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith(b"\x89PNG\r\n")
