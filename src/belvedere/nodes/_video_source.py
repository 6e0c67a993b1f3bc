"""A camera that is not simulated: frames from a video file, a folder of pictures, one
picture, or a real device, read through OpenCV and published as sensor_msgs/Image with its
CameraInfo and image_transport's ``compressed`` topic — the shared part of usb_cam,
video_stream_opencv and image_publisher.

Frames come at the node's rate in graph time (simulated or real), one per tick: a recorded
video plays at the pace the graph's clock sets.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final

import cv2
import numpy as np
from numpy.typing import NDArray

from belvedere.graph import Node
from belvedere.msgs import build, types
from belvedere.nodes._camera_info import camera_info

__all__ = ["FrameSource", "Publishing", "VideoSourceError", "open_source", "start_publishing"]

PICTURES: Final = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".pgm", ".ppm")
Frame = NDArray[Any]
"""A bgr8 picture (height, width, 3)."""
JPEG_QUALITY: Final = 80
"""image_transport's compressed default (``jpeg_quality``)."""


class VideoSourceError(ValueError):
    """A source that cannot be opened (naming it, for the node's one start error)."""


class FrameSource:
    """Frames of a capture (video file, device) or of pictures, each a bgr8 array."""

    def __init__(self, name: str, capture: Any = None, pictures: list[Frame] | None = None) -> None:
        self.name = name
        self.capture = capture
        self.pictures = pictures or []
        self.index = 0
        self.start = 0
        self.stop: int | None = None
        """Frames ``start`` … ``stop - 1`` are played (None: to the end)."""

    @property
    def frame_count(self) -> int | None:
        """How many frames a video file or a set of pictures has (None: a device, or a video
        that does not say)."""
        if self.capture is None:
            return len(self.pictures)
        count = int(self.capture.get(cv2.CAP_PROP_FRAME_COUNT))
        return count if count > 0 else None

    def play_range(self, start: int, stop: int) -> list[str]:
        """Play frames ``start`` … ``stop - 1`` (``stop`` -1: to the end), looping back to
        ``start``; checked as video_stream_opencv checks them. Its warnings, in its words."""
        count = self.frame_count
        warnings: list[str] = []
        if count is None:
            return warnings  # a device: no frames to count
        if stop == -1:
            stop = count
        elif stop > count:
            warnings.append(
                f"Invalid 'stop_frame' {stop} for video which has {count} frames. "
                f"Setting 'stop_frame' to {count}"
            )
            stop = count
        if start >= stop:
            warnings.append(
                f"Invalid 'start_frame' {start}, which exceeds 'stop_frame' {stop}. "
                "Setting 'start_frame' to 0."
            )
            start = 0
        self.start, self.stop = start, stop
        self._seek(start)
        return warnings

    def _seek(self, index: int) -> None:
        self.index = index
        if self.capture is not None:
            self.capture.set(cv2.CAP_PROP_POS_FRAMES, index)

    @property
    def rate(self) -> float | None:
        """The video's own frames per second, when it says."""
        if self.capture is None:
            return None
        fps = float(self.capture.get(cv2.CAP_PROP_FPS))
        return fps if 0.0 < fps < 1000.0 else None

    def read(self, *, loop: bool) -> Frame | None:
        """The next frame; None at the end (unless ``loop``: then the range's first again)."""
        end = self.stop if self.stop is not None or self.capture is not None else len(self.pictures)
        if end is not None and self.index >= end:
            if not loop:
                return None
            self._seek(self.start)
        if self.capture is None:
            frame = self.pictures[self.index]
            self.index += 1
            return frame
        ok, frame = self.capture.read()
        if not ok and loop:
            self._seek(self.start)
            ok, frame = self.capture.read()
        if not ok:
            return None
        self.index += 1
        picture: Frame = frame if frame.ndim == 3 else cv2.cvtColor(frame, cv2.COLOR_GRAY2BGR)
        return picture

    def close(self) -> None:
        if self.capture is not None:
            self.capture.release()


def _picture(path: Path) -> Frame:
    picture = cv2.imread(str(path), cv2.IMREAD_COLOR)
    if picture is None:
        msg = f"{path}: not a picture OpenCV can read"
        raise VideoSourceError(msg)
    frame: Frame = picture
    return frame


def open_source(provider: str | int, *, what: str = "video source") -> FrameSource:
    """A device number or ``/dev/videoN``, a video file, a folder of pictures or a picture."""
    if isinstance(provider, int) or (isinstance(provider, str) and provider.isdigit()):
        return _open_capture(int(provider), f"video device {provider}")
    path = Path(provider).expanduser()
    if str(provider).startswith("/dev/"):
        if not path.exists():
            msg = f"cannot open {what} {provider}: no such device (is a camera plugged in?)"
            raise VideoSourceError(msg)
        return _open_capture(str(path), f"video device {provider}")
    if path.is_dir():
        files = sorted(p for p in path.iterdir() if p.suffix.lower() in PICTURES)
        if not files:
            msg = f"{what} {provider}: a folder without pictures ({', '.join(PICTURES)})"
            raise VideoSourceError(msg)
        return FrameSource(str(path), pictures=[_picture(p) for p in files])
    if not path.is_file():
        msg = f"cannot open {what} {provider}: no such file"
        raise VideoSourceError(msg)
    if path.suffix.lower() in PICTURES:
        return FrameSource(str(path), pictures=[_picture(path)])
    return _open_capture(str(path), f"{what} {provider}")


def _open_capture(target: str | int, name: str) -> FrameSource:
    capture = cv2.VideoCapture(target)
    if not capture.isOpened():
        capture.release()
        msg = f"cannot open {name}: OpenCV can neither open nor decode it"
        raise VideoSourceError(msg)
    return FrameSource(name, capture=capture)


@dataclass
class Publishing:
    """How the frames go out: topics (relative to the node), frame id, flips, calibration."""

    image_topic: str
    info_topic: str
    frame_id: str
    rate: float
    loop: bool
    flip_horizontal: bool = False
    flip_vertical: bool = False
    calibration: dict[str, Any] | None = None
    size: tuple[int, int] | None = None
    """(width, height) to scale each frame to, or None."""


def _image(picture: Frame, header: Any) -> Any:
    height, width = picture.shape[:2]
    data = np.ascontiguousarray(picture).reshape(-1)
    return types().cls("sensor_msgs/Image")(header, height, width, "bgr8", 0, width * 3, data)


def start_publishing(node: Node, source: FrameSource, how: Publishing, on_end: Any) -> None:
    """Publish a frame of ``source`` every 1/rate s of graph time; ``on_end()`` when it ends."""
    image_pub = node.publisher(how.image_topic, "sensor_msgs/Image", queue_size=1)
    info_pub = node.publisher(how.info_topic, "sensor_msgs/CameraInfo", queue_size=1)
    compressed_pub = node.publisher(
        f"{how.image_topic}/compressed", "sensor_msgs/CompressedImage", queue_size=1
    )

    def tick() -> None:
        frame = source.read(loop=how.loop)
        if frame is None:
            source.close()
            on_end()
            return
        if how.size is not None and frame.shape[1::-1] != how.size:
            frame = cv2.resize(frame, how.size)
        if how.flip_horizontal or how.flip_vertical:
            code = -1 if how.flip_horizontal and how.flip_vertical else int(how.flip_horizontal)
            frame = cv2.flip(frame, code)
        header = build.header(node.now_ns(), how.frame_id)
        image_pub.publish(_image(frame, header))
        size = (frame.shape[1], frame.shape[0])
        info_pub.publish(camera_info(how.calibration, header, size))
        if compressed_pub.wanted:  # encoding costs: only for a listener
            ok, jpeg = cv2.imencode(".jpg", frame, [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY])
            if ok:
                compressed_pub.publish(
                    types().cls("sensor_msgs/CompressedImage")(
                        header, "bgr8; jpeg compressed bgr8", jpeg.reshape(-1)
                    )
                )

    node.timer(1.0 / how.rate, tick)
