"""The course's vision scripts, unchanged, on the simulated camera: robot_vision's
cv_bridge_test.py (run by ``belvedere launch`` beside the mbot's camera in the playground)
republishes the camera's picture with a red disc at (60, 60), and its ``cv2.imshow`` window
is an image topic a browser page shows."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

from tests.conftest import EXAMPLES

BELVEDERE = [sys.executable, "-m", "belvedere"]
DEADLINE = 120

PROBE = """\
import rospy
from cv_bridge import CvBridge
from sensor_msgs.msg import Image

rospy.init_node("probe")
bridge = CvBridge()
camera = bridge.imgmsg_to_cv2(rospy.wait_for_message("/camera/image_raw", Image, 60), "bgr8")
marked = bridge.imgmsg_to_cv2(rospy.wait_for_message("/cv_bridge_image", Image, 60))
window = rospy.wait_for_message("/image_window/Image_window", Image, 60)
print("sizes", camera.shape, marked.shape, window.width, window.height, window.encoding)
print("centre", marked[60, 60].tolist())
print("corner same", (marked[-5, -5] == camera[-5, -5]).all())
"""


def _wait_listening(host: subprocess.Popen[str]) -> None:
    """Until the launch's graph is up (so that the probe joins it rather than starting one)."""
    assert host.stdout is not None
    line = host.stdout.readline()
    while line and "listening" not in line:
        line = host.stdout.readline()
    assert "listening" in line


def _probe_beside(launch: list[str], probe_text: str, folder: Path) -> tuple[Any, str]:
    """``belvedere launch LAUNCH…`` and, once its graph listens, the script ``probe_text``
    run beside it: the probe's completed process and the launch's output."""
    probe = folder / "probe.py"
    probe.write_text(probe_text)
    host = subprocess.Popen(
        [*BELVEDERE, "launch", "--package-path", str(EXAMPLES), *launch],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    try:
        _wait_listening(host)
        done = subprocess.run(
            [*BELVEDERE, "run", "--package-path", str(EXAMPLES), str(probe)],
            capture_output=True,
            text=True,
            timeout=DEADLINE,
            check=False,
        )
    finally:
        host.terminate()
        output = host.communicate(timeout=DEADLINE)[0] or ""
    return done, output


def test_cv_bridge_test_marks_the_cameras_picture(tmp_path: Path) -> None:
    launch = EXAMPLES / "robot_vision/launch/cv_bridge_test.launch"
    done, output = _probe_beside([str(launch), "--headless"], PROBE, tmp_path)
    assert done.returncode == 0, done.stderr + output
    lines = done.stdout.splitlines()
    assert lines[0] == "sizes (720, 1280, 3) (720, 1280, 3) 1280 720 bgr8", output
    assert lines[1] == "centre [0, 0, 255]"
    assert lines[2] == "corner same True"
    assert "cv2 window 'Image window' is the image topic /image_window/Image_window" in output


MOTION_PROBE = """\
import rospy
from cv_bridge import CvBridge
from sensor_msgs.msg import Image

rospy.init_node("probe")
bridge = CvBridge()
boxed = 0
for _ in range(40):
    picture = bridge.imgmsg_to_cv2(rospy.wait_for_message("/cv_bridge_image", Image, 60))
    green = (picture[:, :, 1] == 255) & (picture[:, :, 0] == 0) & (picture[:, :, 2] == 0)
    boxed += int(green.sum() > 100)
print("boxed", boxed > 0)
"""


def test_motion_detector_boxes_a_moving_block_in_a_video(tmp_path: Path) -> None:
    import cv2
    import numpy as np

    video = tmp_path / "moving.avi"
    writer = cv2.VideoWriter(str(video), cv2.VideoWriter.fourcc(*"MJPG"), 10.0, (160, 120))
    for i in range(20):
        picture = np.full((120, 160, 3), 40, np.uint8)
        picture[40:80, 5 * i : 5 * i + 40] = (200, 200, 200)
        writer.write(picture)
    writer.release()
    launch = EXAMPLES / "robot_vision/launch/motion_detector.launch"
    done, output = _probe_beside([str(launch), f"video:={video}"], MOTION_PROBE, tmp_path)
    assert done.returncode == 0, done.stderr + output
    assert done.stdout.splitlines() == ["boxed True"], output
