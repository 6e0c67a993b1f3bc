"""map_server's executables in launch files and ``run``: serving a map file, saving the map
received, and the errors their arguments and files give."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from belvedere.cli import main
from belvedere.graph import Graph
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.maps import OccupancyMap, load_map, save_map
from belvedere.packages import PackageIndex

GRID = np.array([[0, 0, 100, -1], [0, 100, 100, -1], [-1, -1, 0, 0]], dtype=np.int8)


@pytest.fixture
def pkg(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A package ``maps_pkg`` with ``maps/office.yaml`` (saved as ``map_saver -f office``
    in its maps directory would)."""
    root = tmp_path / "ws" / "maps_pkg"
    (root / "maps").mkdir(parents=True)
    (root / "launch").mkdir()
    (root / "package.xml").write_text("<package><name>maps_pkg</name></package>")
    monkeypatch.chdir(root / "maps")
    save_map("office", OccupancyMap(GRID, 0.05, (-1.0, -0.5, 0.25)))
    monkeypatch.chdir(tmp_path)
    return root


def _launch(pkg: Path, body: str) -> Path:
    path = pkg / "launch" / "maps.launch"
    path.write_text(f"<launch>\n{body}\n</launch>\n")
    return path


def test_map_server_publishes_the_map_latched_and_serves_it(pkg: Path) -> None:
    launch = _launch(
        pkg,
        '  <node pkg="map_server" type="map_server" name="map_server"'
        ' args="$(find maps_pkg)/maps/office.yaml">\n'
        '    <param name="frame_id" value="world"/>\n  </node>',
    )
    packages = PackageIndex([pkg.parent])
    graph = Graph()
    LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True).start()
    graph.run(duration=0.1)
    # a subscriber that comes late gets the latched map and metadata
    probe = graph.create_node("probe")
    maps: list[Any] = []
    metadata: list[Any] = []
    probe.subscribe("/map", "nav_msgs/OccupancyGrid", maps.append)
    probe.subscribe("/map_metadata", "nav_msgs/MapMetaData", metadata.append)
    graph.run(duration=0.1)
    assert len(maps) == 1
    assert len(metadata) == 1
    msg = maps[0]
    assert msg.header.frame_id == "world"
    assert (msg.info.width, msg.info.height, msg.info.resolution) == (4, 3, 0.05)
    assert np.array_equal(np.asarray(msg.data).reshape(3, 4), GRID)
    # stamped once time is valid (the simulated clock has left zero), as map_server does
    load_time = msg.info.map_load_time
    assert (load_time.sec, load_time.nanosec) != (0, 0)
    assert msg.header.stamp == load_time == metadata[0].map_load_time
    assert metadata[0].origin.orientation.z == pytest.approx(np.sin(0.125))
    response = probe.call_service("/static_map", "nav_msgs/GetMap")
    assert np.array_equal(np.asarray(response.map.data), np.asarray(msg.data))


def test_map_saver_in_a_launch_saves_and_leaves(pkg: Path, tmp_path: Path) -> None:
    out = tmp_path / "saved"
    launch = _launch(
        pkg,
        '  <node pkg="map_server" type="map_server" name="server"'
        ' args="$(find maps_pkg)/maps/office.yaml"/>\n'
        f'  <node pkg="map_server" type="map_saver" name="saver" args="-f {out}">\n'
        '    <remap from="map" to="/map"/>\n  </node>',
    )
    packages = PackageIndex([pkg.parent])
    graph = Graph()
    runtime = LaunchRuntime(load_launch(launch, packages=packages), graph, packages)
    runtime.headless = True
    runtime.start()
    graph.run(duration=0.1)
    assert runtime.finished == {"/saver": 0}
    assert "/saver" not in graph.nodes
    assert "/server" in graph.nodes
    original = pkg / "maps" / "office"
    assert Path(f"{out}.pgm").read_bytes() == Path(f"{original}.pgm").read_bytes()
    saved = Path(f"{out}.yaml").read_text().splitlines()
    assert saved[0] == f"image: {out}.pgm"
    assert saved[1:] == Path(f"{original}.yaml").read_text().splitlines()[1:]


def test_run_map_saver_ends_the_run_when_saved(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    grid = "{info: {resolution: 0.1, width: 3, height: 1}, data: [0, 100, -1]}"
    code = main(
        ["run", "--rtf", "max", "--headless", "--pub", f"/map nav_msgs/OccupancyGrid {grid}",
         "map_server", "map_saver", "-f", str(tmp_path / "mine"), "--occ", "90", "--free", "5"]
    )  # fmt: skip
    assert code == 0
    out, err = capsys.readouterr()
    # the node's log, as a ROS node prints it (on stdout, the wall clock's time and the
    # simulated one)
    lines = [line.split("]: ", 1)[1] for line in out.splitlines()]
    assert all(line.startswith("[INFO] [") for line in out.splitlines())
    assert "Waiting for the map" in lines
    assert lines[-4:] == [
        "Received a 3 X 1 map @ 0.100 m/pix",
        f"Writing map occupancy data to {tmp_path}/mine.pgm",
        f"Writing map occupancy data to {tmp_path}/mine.yaml",
        "Done",
    ]
    assert (tmp_path / "mine.pgm").read_bytes().endswith(b"\n255\n" + bytes([254, 0, 205]))
    assert "required node" not in err  # the run ends with its node, as rosrun's


def test_run_map_server_in_the_old_form(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "old.pgm").write_bytes(b"P5\n2 1\n255\n\x00\xfe")
    code = main(
        ["run", "--rtf", "max", "--duration", "0.1", "--headless", "--echo", "/map",
         "map_server", "map_server", str(tmp_path / "old.pgm"), "0.1", "_negate:=1"]
    )  # fmt: skip
    assert code == 0
    out, err = capsys.readouterr()
    assert "Using deprecated map server interface" in err
    assert "data: [0, 100]" in out  # negated: black is free
    assert "resolution: 0.1" in out


@pytest.mark.parametrize(
    ("args", "error"),
    [
        (["-f"], "map_saver: -f needs a value"),
        (["--occ", "0"], "map_saver: threshold_occupied must be between 1 and 100 (got '0')"),
        (["--free", "101"], "map_saver: threshold_free must be between 0 and 100 (got '101')"),
        (["--occ", "20", "--free", "30"], "threshold_free must be smaller than threshold_occ"),
        (["--bogus"], "map_saver: unknown argument '--bogus'"),
    ],
)
def test_map_saver_arguments(
    args: list[str], error: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["run", "--headless", "map_server", "map_saver", *args]) == 1
    assert error in capsys.readouterr().err


def test_map_saver_help(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", "--headless", "map_server", "map_saver", "-h"]) == 0
    assert capsys.readouterr().out.startswith("Usage: \n  map_saver -h\n  map_saver [--occ")


def test_a_bad_map_in_a_launch_names_the_yaml_line_and_the_node(
    pkg: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    yaml_file = pkg / "maps" / "office.yaml"
    yaml_file.write_text(yaml_file.read_text().replace("resolution: 0.050000", "resolution: -1"))
    launch = _launch(
        pkg,
        '  <node pkg="map_server" type="map_server" name="map_server"\n'
        '        args="$(find maps_pkg)/maps/office.yaml"/>',
    )
    code = main(
        ["launch", "--package-path", str(pkg.parent), "--headless", "--duration", "0.1",
         str(launch)]
    )  # fmt: skip
    assert code == 0  # the node died, not the launch (roslaunch's exit status)
    lines = capsys.readouterr().err.splitlines()
    died = next(i for i, line in enumerate(lines) if "process has died" in line)
    assert lines[died - 2 : died] == [
        f"{yaml_file}:2:13: error: resolution must be a positive number of metres per cell, got -1",
        f"  loading the map of node /map_server at {launch}:2:3",
    ]
    assert lines[died].startswith("[map_server-2] process has died [pid ")


def test_map_server_without_a_map_file(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", "--headless", "map_server", "map_server"]) == 1
    err = capsys.readouterr().err
    assert "map_server takes a map file, got 0 arguments" in err
    assert "USAGE: map_server <map.yaml>" in err


def test_a_saved_map_loads_as_served(pkg: Path) -> None:
    grid = load_map(pkg / "maps" / "office.yaml")
    assert np.array_equal(grid.data, GRID)


def test_map_saver_that_cannot_write_says_so_and_fails(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """map_saver logs the error and would wait for another map; this one ends with status 1
    (a latched map would never come again)."""
    grid = "{info: {resolution: 0.1, width: 1, height: 1}, data: [0]}"
    target = tmp_path / "no" / "such" / "dir" / "map"
    code = main(
        ["run", "--rtf", "max", "--headless", "--pub", f"/map nav_msgs/OccupancyGrid {grid}",
         "map_server", "map_saver", "-f", str(target)]
    )  # fmt: skip
    assert code == 1
    err = capsys.readouterr().err
    assert re.search(
        rf"^\[ERROR\] \[[\d., ]+\]: Couldn't save map file to {re.escape(str(target))}\.pgm: "
        r"No such file or directory$",
        err,
        re.M,
    )
    assert not (tmp_path / "no").exists()
