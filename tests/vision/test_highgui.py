"""cv2's windows for the scripts belvedere runs: each window's topic, the picture imshow
shows for each image type, and cv2 given them only when it has no GUI and display of its
own."""

from __future__ import annotations

import types

import cv2
import numpy as np
import pytest

from belvedere.ros1 import highgui


def test_window_names_become_topics() -> None:
    assert highgui.topic_of("Image window") == "/image_window/Image_window"
    assert highgui.topic_of("3d view!") == "/image_window/w_3d_view"
    assert highgui.topic_of("") == "/image_window/window"


def test_pictures_are_shown_as_opencv_shows_them() -> None:
    picture, encoding = highgui._shown(np.full((2, 3), 0x1234, np.uint16))
    assert encoding == "mono8"
    assert picture.tolist() == [[0x12] * 3] * 2
    picture, encoding = highgui._shown(np.full((2, 2, 3), 0.5, np.float32))
    assert encoding == "bgr8"
    assert picture[0, 0].tolist() == [128, 128, 128]
    assert highgui._shown(np.zeros((2, 2, 4), np.uint8))[1] == "bgra8"


def test_headless_opencv_gets_the_windows(monkeypatch: pytest.MonkeyPatch) -> None:
    assert not highgui.has_own_gui(cv2)  # the wheel belvedere depends on is headless
    fake = types.ModuleType("cv2")
    fake.getBuildInformation = lambda: "  GUI:                           GTK3\n"  # type: ignore[attr-defined]
    monkeypatch.setenv("DISPLAY", ":0")
    highgui.install(fake)
    assert not hasattr(fake, "imshow")  # OpenCV's own windows, on the display
    monkeypatch.delenv("DISPLAY")
    highgui.install(fake)
    assert fake.imshow is highgui.imshow
    assert fake.waitKey(1) == -1
