"""rviz's view controllers, one per browser tab: Orbit and XYOrbit (following a target frame's
position), ThirdPersonFollower (its position and heading) and TopDownOrtho (from above).

viser's camera is a perspective one: TopDownOrtho looks straight down through a narrow field of
view from far above, so that a metre covers ``Scale`` pixels across the map as in rviz.
"""

from __future__ import annotations

import math
import time
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.tf import TFBuffer, TFError, Transform, quat_xyzw_to_matrix

__all__ = [
    "CAMERA_FOV",
    "CAMERA_LOOK_AT",
    "CAMERA_POSITION",
    "VIEW_TYPES",
    "ViewState",
    "camera_pose",
    "floor_point",
]

VIEW_TYPES = ("rviz/Orbit", "rviz/XYOrbit", "rviz/ThirdPersonFollower", "rviz/TopDownOrtho")
FIXED = "<Fixed Frame>"
ORTHO_FOV = math.radians(4.0)
CAMERA_POSITION = (1.2, -1.6, 1.2)
CAMERA_LOOK_AT = (0.0, 0.0, 0.1)
CAMERA_FOV = math.radians(50.0)
"""The initial view without a config: a robot-sized scene seen from the front right, above.
viser's client may move a tab's camera back to it a moment after a view has placed it."""
CLIENT_DEFAULT_POSITION = (3.0, 3.0, 3.0)
"""viser's client's own initial eye, before the server's initial camera reaches it: a loaded
tab can report it after a view has placed its camera."""
RESEND_S = 1.0
"""How long a tab may report an older camera than the one it was last told before it is told
again: a told state can reach viser's server after the tab's report of the newer one."""


def _number(properties: Mapping[str, Any], key: str, default: float) -> float:
    try:
        return float(properties.get(key, default))
    except (TypeError, ValueError):
        return default


def _point(properties: Mapping[str, Any], key: str) -> tuple[float, float, float]:
    p = properties.get(key) or {}
    if not isinstance(p, Mapping):
        return (0.0, 0.0, 0.0)
    return (_number(p, "X", 0.0), _number(p, "Y", 0.0), _number(p, "Z", 0.0))


Array = npt.NDArray[np.float64]


def _apply(m: Array, p: Array) -> Array:
    out: Array = m[:3, :3] @ p + m[:3, 3]
    return out


def _same(a: tuple[Array, Array], b: tuple[Array, Array]) -> bool:
    return bool(np.allclose(a[0], b[0], atol=1e-4) and np.allclose(a[1], b[1], atol=1e-4))


def _yaw(t: Transform) -> float:
    m = quat_xyzw_to_matrix(t.quat_xyzw)
    return math.atan2(float(m[1, 0]), float(m[0, 0]))


def camera_pose(
    cls: str, properties: Mapping[str, Any], target: Transform, viewport_height: int = 700
) -> tuple[
    tuple[float, float, float], tuple[float, float, float], tuple[float, float, float], float
]:
    """(eye, look_at, up, fov) of a view seen from the fixed frame, the target frame at
    ``target``."""
    tx, ty, tz = target.translation
    if cls == "rviz/TopDownOrtho":
        scale = max(_number(properties, "Scale", 10.0), 1e-3)  # pixels per metre
        angle = _number(properties, "Angle", 0.0)
        x, y = _number(properties, "X", 0.0) + tx, _number(properties, "Y", 0.0) + ty
        height = viewport_height / scale / 2 / math.tan(ORTHO_FOV / 2)
        up = (-math.sin(angle), math.cos(angle), 0.0)
        return (x, y, height), (x, y, 0.0), up, ORTHO_FOV
    distance = max(_number(properties, "Distance", 10.0), 0.01)
    pitch = _number(properties, "Pitch", 0.785398)
    yaw = _number(properties, "Yaw", 0.785398)
    fx, fy, fz = _point(properties, "Focal Point")
    if cls == "rviz/ThirdPersonFollower":
        heading = _yaw(target)
        c, s = math.cos(heading), math.sin(heading)
        fx, fy = c * fx - s * fy, s * fx + c * fy
        yaw += heading
    if cls == "rviz/XYOrbit":
        fz = 0.0
    focal = (fx + tx, fy + ty, fz + tz)
    offset = (
        distance * math.cos(pitch) * math.cos(yaw),
        distance * math.cos(pitch) * math.sin(yaw),
        distance * math.sin(pitch),
    )
    eye = (focal[0] + offset[0], focal[1] + offset[1], focal[2] + offset[2])
    fov = _number(properties, "Field of View", 0.785398)  # rviz: 45° vertical
    return eye, focal, (0.0, 0.0, 1.0), fov


@dataclass
class ViewState:
    """One tab's view: its type and properties, and where the target frame was last seen (the
    camera then moves with it, keeping what the user did with the mouse)."""

    cls: str = "rviz/Orbit"
    properties: dict[str, Any] = field(default_factory=dict)
    placed: bool = False
    local: tuple[Array, Array] | None = None
    """(eye, look_at) in the frame the camera follows."""
    written: deque[tuple[Array, Array]] = field(default_factory=lambda: deque(maxlen=150))
    """What this tab's camera was last told (5 s of frames): a camera state the browser
    reports back late is made of these, and is not taken for the user's mouse."""
    synced: bool = False
    """Whether the tab has reported a camera it was told: until then its reports are of the
    camera it had before (viser's initial one, or the previous view's), not the user's mouse."""
    clock: Callable[[], float] = time.monotonic
    sent_at: float = -math.inf
    placed_pixels: int = 0
    """The tab's canvas height the view was placed for (TopDownOrtho's Scale is per pixel)."""
    moved: bool = False
    """Whether the user has moved this tab's camera."""

    def _told(self, seen: tuple[Array, Array]) -> bool:
        """Whether the browser's camera is one it was told, judged by its eye: the user's mouse
        moves the eye (orbit, zoom and pan alike), but a report's target can be one the tab was
        never told. The eye and the target are two messages, so a report between them pairs an
        eye with an older target; and viser's position setter first sends a target shifted with
        the eye from the camera it last heard of, which a report can catch. The initial camera is
        one it was told too: viser's client may go back to it after the view has placed it (its
        initial-camera effect runs after the messages that placed it), and is told again; so is
        the client's own default, which a loaded tab reports before the initial camera."""
        eyes = np.array([*(w[0] for w in self.written), CAMERA_POSITION, CLIENT_DEFAULT_POSITION])
        return bool((np.abs(eyes - seen[0]).max(axis=1) <= 1e-4).any())

    @property
    def target_frame(self) -> str:
        return str(self.properties.get("Target Frame", FIXED))

    def target(self, buffer: TFBuffer, fixed: str) -> Transform | None:
        frame = self.target_frame
        if frame in (FIXED, "", fixed):
            return Transform()
        try:
            return buffer.lookup_transform(fixed, frame)
        except TFError:
            return None

    def _carrier(self, target: Transform) -> Array:
        """The frame the camera rides in: the target's position (and heading, for
        ThirdPersonFollower; without height, for XYOrbit and TopDownOrtho)."""
        x, y, z = target.translation
        if self.cls in ("rviz/XYOrbit", "rviz/TopDownOrtho"):
            z = 0.0
        yaw = _yaw(target) if self.cls == "rviz/ThirdPersonFollower" else 0.0
        c, s = math.cos(yaw), math.sin(yaw)
        m = np.eye(4)
        m[:3, :3] = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
        m[:3, 3] = (x, y, z)
        return m

    def follow(self, camera: Any, buffer: TFBuffer, fixed: str) -> None:
        """Place the camera once, then move it with the target frame (render thread)."""
        target = self.target(buffer, fixed)
        if target is None:
            return
        carrier = self._carrier(target)
        inverse: Array = np.linalg.inv(carrier).astype(np.float64)
        seen = (np.asarray(camera.position, float), np.asarray(camera.look_at, float))
        pixels = int(getattr(camera, "image_height", 0) or 0)
        # A tab may report its canvas before it is laid out (an unsized canvas is 150 px
        # high): a Scale placed for that shows a few square metres of the map, so place it
        # again for a taller canvas until the user takes over. A shorter one is viser lowering
        # its pixel ratio under load, the page's size unchanged: not followed.
        if (
            self.placed
            and self.cls == "rviz/TopDownOrtho"
            and not self.moved
            and pixels > 1.02 * self.placed_pixels
        ):
            self.placed = False
        if not self.placed:
            height = pixels or 700
            self.placed_pixels = height
            eye, look_at, up, fov = camera_pose(self.cls, self.properties, target, height)
            camera.up_direction = up
            camera.fov = fov
            if self.cls == "rviz/TopDownOrtho":
                camera.far = max(1000.0, eye[2] * 2)
            self.placed = True
            self.local = (_apply(inverse, np.array(eye)), _apply(inverse, np.array(look_at)))
        elif self._told(seen):
            self.synced = True
        elif self.synced:
            # The user moved the camera: follow from where they put it.
            self.moved = True
            self.local = (_apply(inverse, seen[0]), _apply(inverse, seen[1]))
        assert self.local is not None
        want = (_apply(carrier, self.local[0]), _apply(carrier, self.local[1]))
        now = self.clock()
        if self.written and _same(want, self.written[-1]):
            if _same(seen, want) or now - self.sent_at < RESEND_S:
                return
        else:
            self.written.append(want)
        self.sent_at = now
        camera.position, camera.look_at = want

    def properties_from(self, camera: Any, buffer: TFBuffer, fixed: str) -> dict[str, Any]:
        """The view's properties as the camera is now (for File > Save Config)."""
        props = dict(self.properties)
        target = self.target(buffer, fixed) or Transform()
        eye, look_at = np.asarray(camera.position), np.asarray(camera.look_at)
        if self.cls == "rviz/TopDownOrtho":
            height = max(float(eye[2] - look_at[2]), 1e-6)
            pixels = int(getattr(camera, "image_height", 0) or 700)
            props["Scale"] = pixels / (2 * height * math.tan(ORTHO_FOV / 2))
            props["X"] = float(look_at[0] - target.translation[0])
            props["Y"] = float(look_at[1] - target.translation[1])
            return props
        rel = eye - look_at
        distance = float(np.linalg.norm(rel))
        yaw = math.atan2(float(rel[1]), float(rel[0]))
        pitch = math.asin(max(-1.0, min(1.0, float(rel[2]) / max(distance, 1e-9))))
        focal = look_at - np.asarray(target.translation)
        if self.cls == "rviz/ThirdPersonFollower":
            heading = _yaw(target)
            c, s = math.cos(-heading), math.sin(-heading)
            focal[:2] = (c * focal[0] - s * focal[1], s * focal[0] + c * focal[1])
            yaw -= heading
        props.update(
            {
                "Distance": distance,
                "Pitch": pitch,
                "Yaw": yaw % (2 * math.pi),
                "Focal Point": {"X": float(focal[0]), "Y": float(focal[1]), "Z": float(focal[2])},
            }
        )
        return props


def floor_point(
    origin: tuple[float, float, float], direction: tuple[float, float, float]
) -> tuple[float, float] | None:
    """Where a click ray meets the floor (z = 0), or None if it points away."""
    if abs(direction[2]) < 1e-9:
        return None
    t = -origin[2] / direction[2]
    if t < 0:
        return None
    return (origin[0] + t * direction[0], origin[1] + t * direction[1])
