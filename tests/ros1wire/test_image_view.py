"""Debian's image_view package on graph images through ``belvedere roscore``: image_saver
writes what a graph node published pixel for pixel (each encoding read as cv_bridge reads
it), and image_view's window shows it on an X display."""

from __future__ import annotations

import shutil
import subprocess
import threading
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from PIL import Image, ImageGrab

from belvedere.graph import Graph
from belvedere.ros1wire import MasterHandle
from tests.ros1wire.conftest import Ros1, publish_until, ros_env
from tests.viewer.rviz_pair import _process
from tests.waiting import DEADLINE, wait_until

IMAGE_VIEW = Path("/usr/lib/image_view")

pytestmark = pytest.mark.usefixtures("needs_debian_ros")


@pytest.fixture(autouse=True)
def _needs_image_view() -> None:
    if not (IMAGE_VIEW / "image_saver").exists():
        pytest.skip("Debian's ros-image-view is not installed (scripts/install.sh --dev)")


def _pattern(height: int, width: int) -> np.ndarray[Any, np.dtype[np.uint8]]:
    """Four saturated quadrants (red, green, blue, yellow as RGB) over a fine gradient: a
    swapped channel or a shifted row shows."""
    img = np.zeros((height, width, 3), dtype=np.uint8)
    h, w = height // 2, width // 2
    img[:h, :w] = (230, 0, 0)
    img[:h, w:] = (0, 230, 0)
    img[h:, :w] = (0, 0, 230)
    img[h:, w:] = (230, 230, 0)
    img[..., 2] += (np.arange(width) % 16).astype(np.uint8)[None, :]
    return img


def _message(rgb: np.ndarray[Any, np.dtype[np.uint8]], encoding: str) -> dict[str, Any]:
    height, width = rgb.shape[:2]
    if encoding == "mono8":
        data = rgb[..., 0]
    elif encoding == "bgr8":
        data = rgb[..., ::-1]
    else:
        data = rgb
    channels = 1 if data.ndim == 2 else 3
    return {
        "header": {"frame_id": "camera"},
        "height": height,
        "width": width,
        "encoding": encoding,
        "step": width * channels,
        "data": np.ascontiguousarray(data).tobytes(),
    }


@pytest.mark.parametrize("encoding", ["rgb8", "bgr8", "mono8"])
def test_image_saver_writes_the_graphs_images_pixel_for_pixel(
    ros_graph: tuple[Graph, MasterHandle], tmp_path: Path, encoding: str
) -> None:
    graph, handle = ros_graph
    pub = graph.create_node("camera").publisher("/camera/image_raw", "sensor_msgs/Image")
    rgb = _pattern(48, 64)
    saver = Ros1(handle.uri).start(
        str(IMAGE_VIEW / "image_saver"),
        "image:=/camera/image_raw",
        f"_filename_format:={tmp_path}/frame%04i.png",
    )
    try:
        publish_until(
            graph,
            pub,
            lambda: len(list(tmp_path.glob("frame*.png"))) >= 3,
            lambda _: _message(rgb, encoding),
            period=0.05,
        )
    finally:
        saver.terminate()
        saver.communicate(timeout=DEADLINE)
    frames = sorted(tmp_path.glob("frame*.png"))
    assert len(frames) >= 3, "image_saver wrote no frames"
    saved = np.asarray(Image.open(frames[-1]).convert("RGB"))
    want = np.repeat(rgb[..., :1], 3, axis=2) if encoding == "mono8" else rgb
    assert saved.shape == want.shape
    assert (saved == want).all(), f"{(saved != want).any(axis=2).sum()} pixels differ"


def test_image_view_shows_a_graph_image_in_its_window(
    ros_graph: tuple[Graph, MasterHandle], tmp_path: Path
) -> None:
    if shutil.which("Xvfb") is None:
        pytest.skip("Xvfb is not installed (scripts/install.sh --dev)")
    graph, handle = ros_graph
    pub = graph.create_node("camera").publisher("/camera/image_raw", "sensor_msgs/Image")
    rgb = _pattern(200, 240)
    display = f":{150 + threading.get_native_id() % 100}"
    with _process(["Xvfb", display, "-screen", "0", "640x480x24"], stderr=subprocess.DEVNULL):
        wait_until(lambda: Path(f"/tmp/.X11-unix/X{display[1:]}").exists(), what="Xvfb")
        env = {
            **ros_env(handle.uri),
            "DISPLAY": display,
            "HOME": str(tmp_path),
            "ROS_PACKAGE_PATH": f"{_described_image_view(tmp_path / 'packages')}:/usr/share",
        }
        shown: list[np.ndarray[Any, np.dtype[np.int64]]] = []

        def on_screen() -> bool:
            shot = np.asarray(ImageGrab.grab(xdisplay=display).convert("RGB")).astype(int)
            shown[:] = [shot]
            return all(_area(shot, colour) > 0.8 * 100 * 120 for colour in _QUADRANTS)

        command = [str(IMAGE_VIEW / "image_view"), "image:=/camera/image_raw"]
        with (
            (tmp_path / "image_view.log").open("wb") as log,
            _process(command, env=env, stdout=log, stderr=subprocess.STDOUT),
        ):
            publish_until(graph, pub, on_screen, lambda _: _message(rgb, "rgb8"), period=0.1)
    areas = [_area(shown[0], colour) for colour in _QUADRANTS]
    assert min(areas) > 0.8 * 100 * 120, f"quadrants on screen (pixels): {areas}"


def _described_image_view(packages: Path) -> Path:
    """A package folder that describes Debian's image_view nodelet to pluginlib: Debian 12's
    ros-image-view ships the library but not its package.xml and nodelet_plugins.xml, so its
    ``image_view`` fails with "class image_view/image ... does not exist" on any master."""
    folder = packages / "image_view"
    folder.mkdir(parents=True)
    library = next(Path("/usr/lib").glob("*/libimage_view.so.*"), None)
    if library is None:
        pytest.skip("Debian's libimage-view is not installed")
    (folder / "libimage_view.so").symlink_to(library)  # pluginlib appends ".so"
    (folder / "package.xml").write_text(
        '<?xml version="1.0"?><package format="2"><name>image_view</name>'
        "<version>1.17.0</version><description>image_view's nodelets</description>"
        '<maintainer email="tests@localhost">tests</maintainer><license>BSD</license>'
        "<exec_depend>nodelet</exec_depend>"  # rospack lists plugins of its dependents only
        '<export><nodelet plugin="${prefix}/nodelet_plugins.xml"/></export></package>'
    )
    (folder / "nodelet_plugins.xml").write_text(
        f'<library path="{folder}/libimage_view"><class name="image_view/image" '
        'type="image_view::ImageNodelet" base_class_type="nodelet::Nodelet"/></library>'
    )
    return packages


_QUADRANTS = ((230, 0, 0), (0, 230, 0), (0, 0, 230), (230, 230, 0))


def _area(shot: np.ndarray[Any, np.dtype[np.int64]], colour: tuple[int, int, int]) -> int:
    """Pixels of the screen within the pattern's gradient of one quadrant's colour."""
    r, g, b = colour
    near = (np.abs(shot[..., 0] - r) <= 2) & (np.abs(shot[..., 1] - g) <= 2)
    blue = shot[..., 2] - b
    return int((near & (blue >= -2) & (blue <= 17)).sum())
