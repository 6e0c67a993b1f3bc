"""Displays without a topic: Grid, RobotModel, TF and Axes — drawn each frame with the latest
transforms, as rviz draws them."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.description.urdf import RobotModel
from belvedere.errors import BelvedereError
from belvedere.graph import NS
from belvedere.tf import TFError, Transform, wxyz_from_xyzw
from belvedere.viewer._display import Display, Prop, color_tuple, line_style
from belvedere.viewer._glb import line_glb
from belvedere.viewer._robot import RobotDrawing
from belvedere.viewer._status import Level

__all__ = ["AxesDisplay", "GridDisplay", "RobotModelDisplay", "TFDisplay"]

FIXED = "<Fixed Frame>"


class _Unstamped(Display):
    stamped = False

    def reference(self, fixed: str) -> Transform | None:
        frame = str(self.values.get("Reference Frame", FIXED))
        return self.latest_pose("" if frame == FIXED else frame, fixed)


GRID_PIECES = 100_000
"""At most this many pieces of line in a Grid (a 1000-cell grid's lines come in longer ones)."""


class GridDisplay(_Unstamped):
    """rviz's grid: lines, not a shader plane (a full-screen grid shader costs a software
    renderer most of its frame rate)."""

    cls = "rviz/Grid"
    type_name = "Grid"
    props = (
        Prop("Reference Frame", FIXED, "frame"),
        Prop("Plane Cell Count", 10, "int", low=1, high=1000, step=1),
        Prop("Normal Cell Count", 0, "int", low=0, high=1000, step=1),
        Prop("Cell Size", 1.0, "float", low=0.01, high=100.0, step=0.01),
        Prop("Line Style", "Lines", "choice", ("Lines", "Billboards")),
        Prop("Line Width", 0.03, "float", low=0.001, high=1.0),
        Prop("Color", (160, 160, 164), "color"),
        Prop("Alpha", 0.5, "float"),
        Prop("Plane", "XY", "choice", ("XY", "XZ", "YZ")),
        Prop("X", 0.0, "float", low=-100.0, high=100.0),
        Prop("Y", 0.0, "float", low=-100.0, high=100.0),
        Prop("Z", 0.0, "float", low=-100.0, high=100.0),
    )

    def update(self, msg: Any, fixed: str) -> None:
        pose = self.reference(fixed)
        if pose is None:
            return
        handle = self.handles.get("grid")
        if handle is None:
            style = line_style(self.values)
            if style["thickness_units"] == "screen":  # rviz's "Lines": GL lines, a pixel wide
                handle = self.ctx.scene.add_glb(
                    f"{self.base}/grid",
                    line_glb(self.pieces(), color_tuple(self.values["Color"])),
                    cast_shadow=False,
                    receive_shadow=False,
                )
            else:
                handle = self.ctx.scene.add_line_segments(
                    f"{self.base}/grid",
                    self.segments(),
                    tuple(self.values["Color"]),
                    **style,
                )
        self.keep("grid", handle, pose)

    def segments(self) -> npt.NDArray[np.float32]:
        """The grid's lines (N, 2, 3) in its reference frame: ``Plane Cell Count`` cells each
        way in the plane, stacked ``Normal Cell Count`` cells along its normal, as rviz's
        ``rviz::Grid`` lays them out around the offset."""
        cells, normal = int(self.values["Plane Cell Count"]), int(self.values["Normal Cell Count"])
        size = float(self.values["Cell Size"])
        half, depth = cells * size / 2, normal * size / 2
        ticks = np.linspace(-half, half, cells + 1)
        levels = np.linspace(-depth, depth, normal + 1)
        lines: list[list[list[float]]] = []
        for h in levels.tolist():
            for t in ticks.tolist():
                lines.append([[t, -half, h], [t, half, h]])
                lines.append([[-half, t, h], [half, t, h]])
        if normal > 0:  # the verticals joining the levels at every crossing
            for a in ticks.tolist():
                for b in ticks.tolist():
                    lines.append([[a, b, -depth], [a, b, depth]])
        segs = np.asarray(lines, dtype=np.float64)
        axes = {"XY": (0, 1, 2), "XZ": (0, 2, 1), "YZ": (1, 2, 0)}[str(self.values["Plane"])]
        placed = np.empty_like(segs)
        placed[..., axes[0]], placed[..., axes[1]], placed[..., axes[2]] = (
            segs[..., 0],
            segs[..., 1],
            segs[..., 2],
        )
        offset = np.array([float(self.values[k]) for k in ("X", "Y", "Z")])
        placed_at: npt.NDArray[np.float32] = (placed + offset).astype(np.float32)
        return placed_at

    def pieces(self) -> npt.NDArray[np.float32]:
        """The grid's lines cut into cell-long pieces (at most :data:`GRID_PIECES` in all):
        a software renderer drops a GL line that crosses the camera's near plane, so a line
        passing beside the camera would vanish whole; a piece vanishes only there."""
        segs = self.segments()
        cells = int(self.values["Plane Cell Count"])
        n = max(1, min(cells, GRID_PIECES // max(1, len(segs))))
        t = np.linspace(0.0, 1.0, n + 1, dtype=np.float32)[None, :, None]
        along = segs[:, :1] + (segs[:, 1:] - segs[:, :1]) * t  # (N, n + 1, 3)
        cut: npt.NDArray[np.float32] = np.stack((along[:, :-1], along[:, 1:]), axis=2).reshape(
            -1, 2, 3
        )
        return cut

    def changed(self, key: str) -> None:
        self.forget("grid")  # rebuilt with the new size, style or colour


class RobotModelDisplay(_Unstamped):
    """The robot from ``Robot Description`` (the viewer's model, or the graph's parameter
    once it is set), its links placed by TF."""

    cls = "rviz/RobotModel"
    type_name = "RobotModel"
    props = (
        Prop("Robot Description", "robot_description", "text"),
        Prop("TF Prefix", "", "text"),
        Prop("Visual Enabled", True, "bool"),
        Prop("Collision Enabled", False, "bool"),
        Prop("Alpha", 1.0, "float"),
    )

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self.drawing: RobotDrawing | None = None
        self.model: RobotModel | None = None
        self.next_look_ns = 0
        super().__init__(*args, **kwargs)

    def _load(self) -> None:
        """The model: the viewer's, else the parameter (looked for once a second)."""
        if self.ctx.model is not None and self.values["Robot Description"] == "robot_description":
            self.model = self.ctx.model
        else:
            now = self.ctx.now_ns()
            if now < self.next_look_ns:
                return
            self.next_look_ns = now + NS
            param = str(self.values["Robot Description"])
            text = self.ctx.node.get_param(f"/{param.lstrip('/')}", None)
            if not isinstance(text, str) or not text:
                self.status.set(
                    "URDF",
                    Level.ERROR,
                    f"Parameter [{param}] does not exist, and was not found by searchParam()",
                )
                return
            try:
                self.model = RobotModel.from_string(text, path=param)
            except BelvedereError as err:
                self.status.set("URDF", Level.ERROR, f"URDF failed to parse: {err.message}")
                self.next_look_ns = 2**62  # the same text will not parse better
                return
        self.drawing = RobotDrawing(
            self.ctx.scene, self.model, root=f"{self.base}/robot", packages=self.ctx.packages
        )
        self.changed("Visual Enabled")
        self.changed("Alpha")
        self.status.set("URDF", Level.OK, "URDF parsed OK")

    def update(self, msg: Any, fixed: str) -> None:
        if self.drawing is None:
            self._load()
            if self.drawing is None:
                return
        prefix = str(self.values["TF Prefix"]).strip("/")
        missing: list[str] = []
        buffer = self.ctx.buffer
        for link, drawing in self.drawing.links.items():
            frame = f"{prefix}/{link}" if prefix else link
            try:
                t = buffer.lookup_transform(fixed, frame)
            except TFError:
                missing.append(link)
                # Not drawn where it never was (the fixed frame's origin) or where it last
                # was: rviz hides a link it has no transform for and says so.
                if drawing.frame.visible:
                    drawing.frame.visible = False
                continue
            drawing.frame.position = t.translation
            drawing.frame.wxyz = wxyz_from_xyzw(t.quat_xyzw)
            if not drawing.frame.visible:
                drawing.frame.visible = True
        if missing:
            self.status.set(
                "Transform",
                Level.ERROR,
                f"No transform from [{missing[0]}] to [{fixed}]"
                + (f" (and {len(missing) - 1} more links)" if len(missing) > 1 else ""),
            )
        else:
            self.status.set("Transform", Level.OK, "Transform OK")

    def changed(self, key: str) -> None:
        if self.drawing is None:
            return
        if key in ("Visual Enabled", "Collision Enabled"):
            self.drawing.show(
                visual=bool(self.values["Visual Enabled"]) and self.enabled,
                collision=bool(self.values["Collision Enabled"]) and self.enabled,
            )
        elif key == "Alpha":
            self.drawing.set_alpha(float(self.values["Alpha"]))

    def show(self, visible: bool) -> None:
        if self.drawing is not None:
            self.drawing.show(
                visual=visible and bool(self.values["Visual Enabled"]),
                collision=visible and bool(self.values["Collision Enabled"]),
            )

    def remove(self) -> None:
        super().remove()
        if self.drawing is not None:
            self.drawing.remove()


class TFDisplay(_Unstamped):
    """Every frame's axes and name, and an arrow from each frame to its parent."""

    cls = "rviz/TF"
    type_name = "TF"
    props = (
        Prop("Show Names", True, "bool"),
        Prop("Show Axes", True, "bool"),
        Prop("Show Arrows", True, "bool"),
        Prop("Marker Scale", 1.0, "float", low=0.01, high=10.0),
        Prop("Frame Timeout", 15.0, "float", low=0.0, high=600.0),
    )

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self.frames: dict[str, tuple[Any, Any]] = {}
        self.updated: dict[str, tuple[int, int]] = {}
        """frame → (its latest time to the fixed frame, when (graph ns) that last changed)"""
        super().__init__(*args, **kwargs)

    def alive(self, frame: str, fixed: str) -> bool:
        """rviz's Frame Timeout: a frame whose transform to the fixed frame has not moved on
        for that long is dead and not drawn (static ones never die)."""
        now = self.ctx.now_ns()
        try:
            latest = self.ctx.buffer.latest_common_time(fixed, frame)
        except TFError:
            return False
        seen, since = self.updated.get(frame, (-1, now))
        if latest != seen or latest == 0:
            since = now
        self.updated[frame] = (latest, since)
        return now - since <= float(self.values["Frame Timeout"]) * NS

    def update(self, msg: Any, fixed: str) -> None:
        buffer = self.ctx.buffer
        scale = float(self.values["Marker Scale"])
        show_names, show_axes = bool(self.values["Show Names"]), bool(self.values["Show Axes"])
        arrows: list[tuple[tuple[float, ...], tuple[float, ...]]] = []
        where: dict[str, Transform] = {}
        for frame in sorted(buffer.frames() | {fixed}):
            try:
                t = buffer.lookup_transform(fixed, frame)
            except TFError:
                continue
            if frame != fixed and not self.alive(frame, fixed):
                pair = self.frames.get(frame)
                if pair is not None:
                    pair[0].visible = pair[1].visible = False
                continue
            where[frame] = t
            pair = self.frames.get(frame)
            if pair is None:
                axes = self.ctx.scene.add_frame(
                    f"{self.base}/{frame}", axes_length=0.1, axes_radius=0.005
                )
                label = self.ctx.scene.add_label(f"{self.base}/{frame}/name", frame)
                pair = self.frames[frame] = (axes, label)
                self.handles[f"frame:{frame}"] = axes
                self.handles[f"name:{frame}"] = label
            axes, label = pair
            axes.position = t.translation
            axes.wxyz = wxyz_from_xyzw(t.quat_xyzw)
            axes.scale = scale
            axes.show_axes = show_axes
            axes.visible = True
            label.visible = show_names
        if self.values["Show Arrows"]:
            for frame, t in where.items():
                parent = buffer.parent(frame)
                if parent in where:
                    arrows.append((t.translation, where[parent].translation))
        if arrows:
            segs = np.array(arrows, dtype=np.float32)
            handle = self.handles.get("arrows")
            if handle is not None and handle.points.shape == segs.shape:
                handle.points = segs  # moved in place: a new node each frame costs the browser
            else:
                handle = self.ctx.scene.add_line_segments(
                    f"{self.base}/arrows", segs, (255, 220, 0), thickness=0.004 * math.sqrt(scale)
                )
            self.keep("arrows", handle)
        else:
            self.forget("arrows")
        self.status.set("Frames", Level.OK, f"{len(where)} frames")

    def changed(self, key: str) -> None:
        if key == "Marker Scale":
            self.forget("arrows")  # rebuilt with the new thickness

    def remove(self) -> None:
        super().remove()
        self.frames.clear()


class AxesDisplay(_Unstamped):
    cls = "rviz/Axes"
    type_name = "Axes"
    props = (
        Prop("Reference Frame", FIXED, "frame"),
        Prop("Length", 1.0, "float", low=0.01, high=10.0),
        Prop("Radius", 0.1, "float", low=0.001, high=1.0),
    )

    def update(self, msg: Any, fixed: str) -> None:
        pose = self.reference(fixed)
        if pose is None:
            return
        handle = self.handles.get("axes")
        if handle is None:
            handle = self.ctx.scene.add_frame(
                f"{self.base}/axes",
                axes_length=float(self.values["Length"]),
                axes_radius=float(self.values["Radius"]),
            )
        self.keep("axes", handle, pose)

    def changed(self, key: str) -> None:
        self.forget("axes")
