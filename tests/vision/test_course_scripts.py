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


FACE_PROBE = """\
import numpy as np
import rospy
from cv_bridge import CvBridge
from sensor_msgs.msg import Image

rospy.init_node("probe")
bridge = CvBridge()
for _ in range(20):
    picture = bridge.imgmsg_to_cv2(rospy.wait_for_message("/cv_bridge_image", Image, 60))
    frame = (picture[:, :, 0] == 50) & (picture[:, :, 1] == 255) & (picture[:, :, 2] == 50)
    if frame.sum() > 100:
        rows, cols = np.nonzero(frame)
        print("framed", (cols.min() + cols.max()) // 2, (rows.min() + rows.max()) // 2)
        break
else:
    print("no face framed")
"""


def _face(size: float) -> Any:
    """A drawn face (grey): an oval, eyes and brows darker, a lighter nose, a mouth — the
    contrasts a frontal Haar cascade looks for — centred at (160, 120) of 320 x 240."""
    import cv2
    import numpy as np

    img = np.full((240, 320), 60, np.uint8)

    def at(dx: float, dy: float) -> tuple[int, int]:
        return 160 + round(dx * size), 120 + round(dy * size)

    def axes(a: float, b: float) -> tuple[int, int]:
        return round(a * size), round(b * size)

    cv2.ellipse(img, at(0, 0), axes(40, 52), 0, 0, 360, 200, -1)
    for side in (-17, 17):
        cv2.ellipse(img, at(side, -12), axes(9, 5), 0, 0, 360, 40, -1)
        cv2.line(img, at(side - 11, -24), at(side + 11, -24), 60, max(1, round(4 * size)))
    cv2.ellipse(img, at(0, 8), axes(6, 10), 0, 0, 360, 170, -1)
    cv2.ellipse(img, at(0, 28), axes(15, 5), 0, 0, 360, 70, -1)
    return cv2.cvtColor(cv2.GaussianBlur(img, (5, 5), 0), cv2.COLOR_GRAY2BGR)


def test_face_detector_frames_a_face_in_a_video(tmp_path: Path) -> None:
    """face_detector.py with OpenCV's own cascades (the package's data folder, as the course
    keeps them, given here as the wheel's folder)."""
    import cv2

    video = tmp_path / "face.avi"
    writer = cv2.VideoWriter(str(video), cv2.VideoWriter.fourcc(*"MJPG"), 10.0, (320, 240))
    for i in range(20):
        writer.write(_face(0.9 + 0.01 * i))
    writer.release()
    launch = EXAMPLES / "robot_vision/launch/face_detector.launch"
    cascades = f"cascades:={cv2.data.haarcascades.rstrip('/')}"  # type: ignore[attr-defined]
    done, output = _probe_beside([str(launch), f"video:={video}", cascades], FACE_PROBE, tmp_path)
    assert done.returncode == 0, done.stderr + output
    words = done.stdout.split()
    assert words[0] == "framed", output
    assert abs(int(words[1]) - 160) < 15, words
    assert abs(int(words[2]) - 120) < 15, words


def test_face_detector_without_its_cascades_says_which(tmp_path: Path) -> None:
    import cv2

    video = tmp_path / "face.avi"
    writer = cv2.VideoWriter(str(video), cv2.VideoWriter.fourcc(*"MJPG"), 10.0, (320, 240))
    for _ in range(5):
        writer.write(_face(1.0))
    writer.release()
    launch = EXAMPLES / "robot_vision/launch/face_detector.launch"
    probe = 'import rospy\nrospy.init_node("probe")\nrospy.sleep(1.0)\n'
    done, output = _probe_beside(
        [str(launch), f"video:={video}", f"cascades:={tmp_path / 'none'}"], probe, tmp_path
    )
    assert done.returncode == 0, done.stderr
    assert f"cannot load the Haar cascade {tmp_path / 'none'}/haarcascade_frontalface_alt" in output
