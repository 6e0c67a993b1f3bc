"""Viewer parts that need no browser: mesh-path guard, rviz configs, floor clicks, CLI errors,
the Map display's updates."""

from __future__ import annotations

import socket
from pathlib import Path

import numpy as np
import pytest

from belvedere.cli import main
from belvedere.graph import Graph
from belvedere.maps import OccupancyMap, grid_message
from belvedere.packages import PackageIndex
from belvedere.viewer import (
    MeshAccessError,
    Viewer,
    allowed_mesh_path,
    floor_point,
)
from tests.conftest import EXAMPLES
from tests.waiting import wait_until

PKG = EXAMPLES / "mbot_description"


@pytest.mark.parametrize(
    "filename",
    [
        "package://mbot_description/../../../etc/passwd",
        "/etc/passwd",
        "file:///etc/hostname",
        "../../../../etc/passwd",
    ],
)
def test_meshes_outside_package_roots_are_refused(filename: str) -> None:
    packages = PackageIndex([EXAMPLES])
    model = PKG / "urdf" / "xacro" / "gazebo" / "mbot_gazebo.xacro"
    with pytest.raises(MeshAccessError, match="outside the package roots; refused"):
        allowed_mesh_path(filename, model_path=str(model), packages=packages, at=None)


def test_meshes_inside_package_roots_resolve() -> None:
    packages = PackageIndex([EXAMPLES])
    path = allowed_mesh_path(
        "package://mbot_description/meshes/kinect.dae", model_path=None, packages=packages, at=None
    )
    assert path == (PKG / "meshes" / "kinect.dae").resolve()


def test_floor_point() -> None:
    assert floor_point((0.0, 0.0, 2.0), (0.5, 0.0, -1.0)) == (1.0, 0.0)
    assert floor_point((0.0, 0.0, 2.0), (0.0, 0.0, 1.0)) is None
    assert floor_point((0.0, 0.0, 2.0), (1.0, 0.0, 0.0)) is None


def test_display_of_a_broken_model_is_an_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = tmp_path / "bad.urdf"
    bad.write_text('<robot name="r"><link name="a"/><link name="b"/></robot>')
    assert main(["display", str(bad), "--port", "0"]) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"{bad}:1:1: error: two root links found")


def test_a_growing_map_is_redrawn_as_it_grows() -> None:
    """The Map display shows the latest /map: a SLAM map that grows is drawn again (and a
    map that does not change is not rebuilt every frame)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    graph = Graph(sim_time=False)
    viewer = Viewer(graph, port=port, fixed_frame="map")
    try:
        display = viewer.add_display("OccupancyGrid", "/map")
        pub = graph.create_node("slam").publisher("/map", "nav_msgs/OccupancyGrid", latch=True)
        graph.start(rtf=None)

        def width() -> int:
            drawn = getattr(display, "drawn", None)
            return int(drawn.info.width) if drawn is not None else 0

        small = grid_message(OccupancyMap(np.zeros((4, 5), np.int8), 0.05))
        graph.executor.post(lambda: pub.publish(small))
        wait_until(lambda: width() == 5, what="the 5-cell-wide map drawn")
        handle = display.handles["grid"]
        image = getattr(display, "image", None)
        assert image is not None
        assert image.shape == (4, 5, 4)
        assert (image[..., :3] == 255).all()  # free: white
        assert (image[..., 3] == round(0.7 * 255)).all()  # rviz's Map alpha 0.7
        frames = viewer.frames_rendered
        wait_until(lambda: viewer.frames_rendered > frames + 2, what="more frames")
        assert display.handles["grid"] is handle  # the same map: not rebuilt
        bigger = grid_message(OccupancyMap(np.full((8, 10), 100, np.int8), 0.05))
        graph.executor.post(lambda: pub.publish(bigger))
        wait_until(lambda: width() == 10, what="the grown map drawn")
        assert display.handles["grid"] is not handle
        image = getattr(display, "image", None)
        assert image is not None
        assert image.shape == (8, 10, 4)
        assert (image[..., :3] == 0).all()  # occupied: black
    finally:
        viewer.close()
        graph.shutdown()
