"""Python-2-era ``cv2.cv`` in the scripts belvedere runs: its constants translated to
OpenCV 4's with one notice, the OpenCV 1 C API an error saying where translation stops."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import cv2
import pytest

from belvedere.ros1.cv_legacy import legacy_module, translate

SCRIPT = """\
import cv2
import cv2.cv as cv
print(cv.CV_CAP_PROP_FPS == cv2.CAP_PROP_FPS, cv.CV_RGB2HSV == cv2.COLOR_RGB2HSV)
print(cv.CV_AA == cv2.LINE_AA, cv.RGB(255, 0, 0))
cv.CreateImage((2, 2), 8, 3)
"""

# rbx1_vision's style: Python 2, ``from cv2 import cv``, its window calls and an integer
# division for WaitKey's delay
PYTHON2 = """\
from cv2 import cv as cv
import cv2
import numpy as np
fps = 25
cv.NamedWindow("Video Playback", True)
cv.MoveWindow("Video Playback", 375, 25)
frame = np.zeros((48, 64, 3), np.uint8)
cv2.putText(frame, "FPS: " + str(fps), (10, 20), cv2.FONT_HERSHEY_SIMPLEX, 0.5, cv.RGB(255, 255, 0))
cv2.imshow("Video Playback", frame)
key = cv.WaitKey(1000 / fps)
print "key", key, frame[15:21, 10:40, 1].max()
"""


def test_constants_are_translated_by_name() -> None:
    assert translate(cv2, "CV_BGR2GRAY") == cv2.COLOR_BGR2GRAY
    assert translate(cv2, "CV_HAAR_SCALE_IMAGE") == cv2.CASCADE_SCALE_IMAGE
    assert translate(cv2, "CV_THRESH_BINARY") == cv2.THRESH_BINARY
    assert translate(cv2, "CV_TERMCRIT_ITER") == cv2.TERM_CRITERIA_MAX_ITER
    assert translate(cv2, "CV_FONT_HERSHEY_SIMPLEX") == cv2.FONT_HERSHEY_SIMPLEX
    assert legacy_module(cv2).RGB(10, 20, 30) == (30, 20, 10, 0.0)
    with pytest.raises(AttributeError, match="the OpenCV 1 C API, IplImage and CvMat, is gone"):
        translate(cv2, "fromarray")


def test_a_script_imports_cv2_cv(tmp_path: Path) -> None:
    script = tmp_path / "old.py"
    script.write_text(SCRIPT)
    run = subprocess.run(
        [sys.executable, "-m", "belvedere", "run", str(script)],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert run.stdout.splitlines() == ["True True", "True (0, 0, 255, 0.0)"]
    assert run.stderr.count("cv2.cv is OpenCV 2's") == 1
    assert "AttributeError: cv2.cv.CreateImage: OpenCV 4 has no cv2.cv" in run.stderr
    assert run.returncode == 1


def test_a_python2_script_with_cv2_cv_windows(tmp_path: Path) -> None:
    script = tmp_path / "playback.py"
    script.write_text(PYTHON2)
    run = subprocess.run(
        [sys.executable, "-m", "belvedere", "run", str(script)],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines() == ["key -1 255"]
