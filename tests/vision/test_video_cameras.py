"""Cameras that are not simulated: video_stream_opencv playing a video (written here with
OpenCV's VideoWriter) in graph time with its calibration's CameraInfo and a compressed
topic; image_publisher on a folder of pictures; usb_cam without its device, and a bad
calibration file, each one error naming what is wrong."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import cv2
import numpy as np
import pytest

from belvedere.errors import ParseError
from belvedere.graph import Graph
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.packages import PackageIndex

CALIBRATION = """\
image_width: 64
image_height: 48
camera_name: test_camera
camera_matrix:
  rows: 3
  cols: 3
  data: [50.0, 0.0, 32.0, 0.0, 50.0, 24.0, 0.0, 0.0, 1.0]
distortion_model: plumb_bob
distortion_coefficients:
  rows: 1
  cols: 5
  data: [0.1, -0.2, 0.0, 0.0, 0.0]
rectification_matrix:
  rows: 3
  cols: 3
  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]
projection_matrix:
  rows: 3
  cols: 4
  data: [50.0, 0.0, 32.0, 0.0, 0.0, 50.0, 24.0, 0.0, 0.0, 0.0, 1.0, 0.0]
"""


def _frame(i: int) -> Any:
    """Frame ``i``: black with a white block whose column says which frame it is."""
    picture = np.zeros((48, 64, 3), np.uint8)
    picture[16:32, 4 * i : 4 * i + 8] = 255
    return picture


def _video(path: Path, count: int) -> Path:
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter.fourcc(*"MJPG"), 10.0, (64, 48))
    assert writer.isOpened()
    for i in range(count):
        writer.write(_frame(i))
    writer.release()
    return path


def _column(msg: Any) -> int:
    picture = np.asarray(msg.data).reshape(msg.height, msg.width, 3)
    return int(np.argmax(picture[24, :, 0] > 128)) // 4


def _run(launch: Path, seconds: float, topics: dict[str, str]) -> dict[str, list[Any]]:
    packages = PackageIndex([])
    graph = Graph()
    LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True).start()
    got: dict[str, list[Any]] = {topic: [] for topic in topics}
    probe = graph.create_node("probe")
    for topic, kind in topics.items():
        probe.subscribe(topic, kind, got[topic].append, queue_size=100)
    graph.run(duration=seconds)
    return got


def test_a_video_is_a_camera_in_graph_time(tmp_path: Path) -> None:
    video = _video(tmp_path / "clip.avi", 8)
    (tmp_path / "calibration.yaml").write_text(CALIBRATION)
    launch = tmp_path / "camera.launch"
    launch.write_text(
        f"""<launch><group ns="camera">
          <node pkg="video_stream_opencv" type="video_stream" name="camera_stream">
            <param name="video_stream_provider" value="{video}"/>
            <param name="frame_id" value="cam_optical"/>
            <param name="camera_info_url" value="file://{tmp_path}/calibration.yaml"/>
          </node>
        </group></launch>"""
    )
    got = _run(
        launch,
        1.5,
        {
            "/camera/image_raw": "sensor_msgs/Image",
            "/camera/camera_info": "sensor_msgs/CameraInfo",
            "/camera/image_raw/compressed": "sensor_msgs/CompressedImage",
        },
    )
    images = got["/camera/image_raw"]
    # the video's own 10 Hz: all 8 frames in order within 1.5 s, then the node ends
    assert [_column(m) for m in images] == list(range(8))
    assert [m.header.stamp.nanosec for m in images[:2]] == [100_000_000, 200_000_000]
    assert images[0].encoding == "bgr8"
    assert images[0].header.frame_id == "cam_optical"
    info = got["/camera/camera_info"][0]
    assert list(info.K) == [50.0, 0.0, 32.0, 0.0, 50.0, 24.0, 0.0, 0.0, 1.0]
    assert list(info.D) == [0.1, -0.2, 0.0, 0.0, 0.0]
    assert (info.width, info.height, info.distortion_model) == (64, 48, "plumb_bob")
    compressed = got["/camera/image_raw/compressed"][3]
    assert compressed.format == "bgr8; jpeg compressed bgr8"
    decoded = cv2.imdecode(np.asarray(compressed.data), cv2.IMREAD_COLOR)
    assert decoded is not None
    assert np.abs(decoded.astype(int) - _frame(3)).mean() < 8


def test_image_publisher_plays_a_folder_of_pictures(tmp_path: Path) -> None:
    folder = tmp_path / "pictures"
    folder.mkdir()
    for i in range(3):
        cv2.imwrite(str(folder / f"{i:02d}.png"), _frame(i))
    launch = tmp_path / "pictures.launch"
    launch.write_text(
        f"""<launch>
          <node pkg="image_publisher" type="image_publisher" name="pics" args="{folder}">
            <param name="publish_rate" value="5"/>
          </node>
        </launch>"""
    )
    got = _run(launch, 1.0, {"/pics/image_raw": "sensor_msgs/Image"})
    assert [_column(m) for m in got["/pics/image_raw"]] == [0, 1, 2, 0, 1]


def _start_error(tmp_path: Path, node: str) -> str:
    launch = tmp_path / "bad.launch"
    launch.write_text(f"<launch>\n{node}\n</launch>")
    packages = PackageIndex([])
    with pytest.raises(ParseError) as raised:
        LaunchRuntime(load_launch(launch, packages=packages), Graph(), packages).start()
    return str(raised.value)


def test_usb_cam_without_its_device_says_so(tmp_path: Path) -> None:
    text = _start_error(
        tmp_path,
        """<node pkg="usb_cam" type="usb_cam_node" name="usb_cam">
             <param name="video_device" value="/dev/video_belvedere_none"/></node>""",
    )
    assert "bad.launch:2" in text
    assert "cannot open video device /dev/video_belvedere_none: no such device" in text


def test_a_bad_calibration_names_its_line(tmp_path: Path) -> None:
    video = _video(tmp_path / "clip.avi", 2)
    calibration = tmp_path / "calibration.yaml"
    calibration.write_text(
        CALIBRATION.replace("data: [50.0, 0.0, 32.0, 0.0, 50.0, 24.0,", "data: [")
    )
    text = _start_error(
        tmp_path,
        f"""<node pkg="video_stream_opencv" type="video_stream" name="v">
             <param name="video_stream_provider" value="{video}"/>
             <param name="camera_info_url" value="file://{calibration}"/></node>""",
    )
    assert f"{calibration}:7" in text
    assert "calibration entry camera_matrix: expected {rows, cols, data} with data of 9" in text


def test_video_stream_opencvs_camera_launch(tmp_path: Path) -> None:
    video = _video(tmp_path / "clip.avi", 4)
    launch = tmp_path / "play.launch"
    launch.write_text(
        f"""<launch>
          <include file="$(find video_stream_opencv)/launch/camera.launch">
            <arg name="camera_name" value="videofile"/>
            <arg name="video_stream_provider" value="{video}"/>
            <arg name="fps" value="20"/>
            <arg name="loop_videofile" value="true"/>
            <arg name="flip_horizontal" value="true"/>
          </include>
        </launch>"""
    )
    got = _run(launch, 0.5, {"/videofile/image_raw": "sensor_msgs/Image"})
    # 20 Hz, looping; flipped left to right, the block of frame i starts at 64 - 4 i - 8
    columns = [_column(m) for m in got["/videofile/image_raw"]]
    assert columns == [(64 - 4 * i - 8) // 4 for i in (0, 1, 2, 3, 0, 1, 2, 3, 0, 1)]
    assert got["/videofile/image_raw"][0].header.frame_id == "videofile"


def test_start_and_stop_frames_and_the_camera_fps_cap(tmp_path: Path) -> None:
    """video_stream_opencv's start_frame/stop_frame: frames 2 … 4 of 8, looping; ``fps``
    above ``set_camera_fps`` publishes at the camera's rate."""
    video = _video(tmp_path / "clip.avi", 8)
    launch = tmp_path / "range.launch"
    launch.write_text(
        f"""<launch><node pkg="video_stream_opencv" type="video_stream" name="range">
             <param name="video_stream_provider" value="{video}"/>
             <param name="fps" value="40.0"/>
             <param name="set_camera_fps" value="20.0"/>
             <param name="start_frame" value="2"/>
             <param name="stop_frame" value="5"/>
             <param name="loop_videofile" value="true"/>
           </node></launch>"""
    )
    images = _run(launch, 0.4, {"/image_raw": "sensor_msgs/Image"})["/image_raw"]
    assert [_column(m) for m in images] == [2, 3, 4, 2, 3, 4, 2, 3]
    assert [m.header.stamp.nanosec for m in images[:2]] == [50_000_000, 100_000_000]


def test_a_stop_frame_past_the_end_plays_to_the_end(tmp_path: Path) -> None:
    video = _video(tmp_path / "clip.avi", 4)
    launch = tmp_path / "past.launch"
    launch.write_text(
        f"""<launch><node pkg="video_stream_opencv" type="video_stream" name="past">
             <param name="video_stream_provider" value="{video}"/>
             <param name="start_frame" value="1"/>
             <param name="stop_frame" value="100"/>
           </node></launch>"""
    )
    images = _run(launch, 1.0, {"/image_raw": "sensor_msgs/Image"})["/image_raw"]
    assert [_column(m) for m in images] == [1, 2, 3]
