"""A 2D simulation's window in the 3D scene: turtlesim's canvas (background, trails and
turtles) as a picture lying on the floor, where its world's coordinates are the fixed frame's.

The picture is sent again only when it changed, and at most ``rate_hz`` times a second: a
500 by 500 PNG is cheap to send but not at the render rate."""

from __future__ import annotations

import threading
import time
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

if TYPE_CHECKING:
    import viser

__all__ = ["Canvas", "CanvasDrawing"]


class Canvas(Protocol):
    """What the viewer needs of a 2D simulation (turtlesim_node)."""

    @property
    def cmd_vel(self) -> str:
        """The topic the viewer's teleop drives (turtlesim's ``turtle1/cmd_vel``)."""
        ...

    def picture(self) -> tuple[np.ndarray[Any, np.dtype[np.uint8]], float]:
        """The window as the simulation shows it (rows from the top) and the size of a pixel
        in metres; pixel (row r, column c) is centred on (c, (rows - 1 - r)) times that."""
        ...


class CanvasDrawing:
    """A :class:`Canvas` drawn in ``scene`` under ``name``."""

    def __init__(
        self, scene: viser.SceneApi, canvas: Canvas, name: str = "/canvas", rate_hz: float = 10.0
    ) -> None:
        self.scene = scene
        self.canvas = canvas
        self.name = name
        self.period = 1.0 / rate_hz
        self.next_at = 0.0
        self.shown: np.ndarray[Any, np.dtype[np.uint8]] | None = None
        self.handle: Any = None
        # the viewer's render thread and a caller's render_once may both draw: one at a time,
        # so a caller never returns while the other is half-way through a picture
        self._lock = threading.Lock()

    def update(self) -> None:
        with self._lock:
            self._update()

    def _update(self) -> None:
        now = time.monotonic()
        if now < self.next_at:
            return
        self.next_at = now + self.period
        image, pixel = self.canvas.picture()
        if self.shown is not None and np.array_equal(image, self.shown):
            return
        rows, cols = image.shape[:2]
        self.handle = self.scene.add_image(
            self.name,
            np.ascontiguousarray(image[::-1]),  # viser puts row 0 at the plane's lowest y
            render_width=cols * pixel,
            render_height=rows * pixel,
            format="png",
            cast_shadow=False,
            receive_shadow=False,
            # just under z = 0, where a Grid display's plane would fight it for each pixel
            position=((cols - 1) * pixel / 2, (rows - 1) * pixel / 2, -0.003),
        )
        self.shown = image
