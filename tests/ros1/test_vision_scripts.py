"""The course's vision scripts, unchanged, on a camera of the graph: cv_bridge_test.py draws
its red circle and republishes, and its ``cv2.imshow`` window (no screen here) is an image
topic the browser can show."""

from __future__ import annotations

import subprocess
import threading
from functools import partial
from typing import Any

import numpy as np

from belvedere.graph import Graph, ZenohTransport
from belvedere.pyscripts import script_command
from tests.conftest import EXAMPLES
from tests.waiting import wait_until

SCRIPTS = EXAMPLES / "robot_vision" / "scripts"


def _pixels(msg: Any) -> Any:
    channels = msg.step // msg.width
    return np.asarray(msg.data, dtype=np.uint8).reshape(msg.height, msg.width, channels)


def test_cv_bridge_test_draws_its_circle_and_shows_its_window(endpoint: str) -> None:
    graph = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint), clock_hz=None)
    node = graph.create_node("camera")
    camera = node.publisher("/camera/image_raw", "sensor_msgs/Image")
    republished: list[Any] = []
    windows: list[Any] = []
    node.subscribe("/cv_bridge_image", "sensor_msgs/Image", republished.append)
    node.subscribe("/cv_windows/Image_window", "sensor_msgs/Image", windows.append)
    graph.start(rtf=None)
    grey = np.full((480, 640, 3), 90, dtype=np.uint8)
    frame = {
        "encoding": "rgb8",
        "height": 480,
        "width": 640,
        "step": 640 * 3,
        "data": grey.tobytes(),
    }
    script = subprocess.Popen(
        script_command(SCRIPTS / "cv_bridge_test.py"),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    stop = threading.Event()

    def stream() -> None:
        while not stop.wait(0.1):
            graph.executor.post(partial(camera.publish_data, frame))

    threading.Thread(target=stream, daemon=True).start()
    try:
        wait_until(lambda: republished and windows, what="the script's image and window")
    finally:
        stop.set()
        script.terminate()
        _, err = script.communicate(timeout=30)
        graph.shutdown()
    image = _pixels(republished[-1])
    assert republished[-1].encoding == "bgr8"
    assert image[60, 60].tolist() == [0, 0, 255]  # red, in BGR
    assert image[60, 91].tolist() == [90, 90, 90]  # past the circle's 30 px radius
    assert image[200, 300].tolist() == [90, 90, 90]
    assert np.array_equal(_pixels(windows[-1]), image)
    assert "/cv_windows/Image_window" in err
