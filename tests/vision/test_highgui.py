"""cv2's windows for the scripts belvedere runs: each window's topic, the picture imshow
shows for each image type, and cv2 given them only when it has no GUI and display of its
own."""

from __future__ import annotations

import types
from pathlib import Path

import cv2
import numpy as np
import pytest

from belvedere.graph import Graph, ZenohTransport
from belvedere.ros1 import highgui
from belvedere.viewer._windows import is_window_topic, typed_keys
from tests.vision.window_script import WINDOW, WindowScript
from tests.waiting import wait_until


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


def test_typed_keys_are_opencvs_codes() -> None:
    assert typed_keys("", "q") == [ord("q")]
    assert typed_keys("q", "q\n") == [13]
    assert typed_keys("abc", "ac") == [8]  # one character deleted: Backspace
    assert typed_keys("ab", "aXb") == [ord("X")]
    assert typed_keys("ab", "ab") == []


def test_the_viewer_takes_window_topics_only() -> None:
    assert is_window_topic(highgui.topic_of("Image window"))
    assert not is_window_topic(highgui.key_topic_of("Image window"))  # its keys: not a window
    assert not is_window_topic("/camera/image_raw")
    assert not is_window_topic("/image_window")


def test_a_key_on_the_window_topic_is_what_wait_key_returns(endpoint: str, tmp_path: Path) -> None:
    graph = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint, serve_params=False))
    typist = graph.create_node("typist").publisher(highgui.key_topic_of(WINDOW), "std_msgs/Int32")
    names: list[str] = []
    graph.create_node("reader").subscribe(
        highgui.topic_of(WINDOW) + highgui.NAME_SUFFIX,
        "std_msgs/String",
        lambda msg: names.append(msg.data),
    )
    graph.start(rtf=None)
    script = WindowScript(tmp_path, count=2, destroy=False)
    try:
        # waitKey(0) without a window returns at once; with one, the delay ends the wait
        assert script.wait_for("no window:") == "no window: -1"
        assert script.wait_for("shown:") == "shown: -1"
        wait_until(lambda: typist.wanted, what="the script to subscribe to its window's keys")
        wait_until(lambda: names, what="the window's name")
        assert names == [WINDOW]  # as the script spelled it: "keys test", on /…/keys_test/name
        typist.publish_data({"data": ord("q")})
        typist.publish_data({"data": 27})
        assert script.wait_for("waiting") == "waiting"
        assert [line for line in script.lines if line.startswith("key:")] == [
            "key: 113",
            "key: 27",
        ]
        # a waitKey(0) no key will end: rospy's shutdown (Ctrl-C) does
        script.stop()
        assert script.wait_for("ended:") == "ended: -1"
    finally:
        script.stop()
        graph.shutdown()
