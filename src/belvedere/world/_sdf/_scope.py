"""What every SDF element family reads with: the SDF version, warnings, ``<pose>``s,
names, and ``<frame>``s in a scope's frame graph."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from belvedere.description.urdf import Pose
from belvedere.errors import SourceLocation
from belvedere.world._elements import child as _child
from belvedere.world._elements import floats as _floats
from belvedere.world._frames import FrameGraph, Matrix4
from belvedere.world._model import SDFError, WorldFrame, WorldModelEntry
from belvedere.world._paths import ModelPaths
from belvedere.world._poses import quat_xyzw_to_rpy
from belvedere.xmldom import Element

__all__ = ["ElementReader"]


def _version(text: str) -> tuple[int, int]:
    parts = [int(p) for p in text.strip().split(".")[:2] if p.isdigit()]
    major, minor = [*parts, 0, 0][:2]
    return major, minor


def _pose_at(el: Element) -> SourceLocation | None:
    """Where an element's pose is written (its ``<pose>``, else the element)."""
    pose = _child(el, "pose")
    return (pose if pose is not None else el).loc


def _rotate(rotation: Matrix4, v: tuple[float, float, float]) -> tuple[float, float, float]:
    r = rotation[:3, :3] @ np.asarray(v, dtype=np.float64)
    return (float(r[0]), float(r[1]), float(r[2]))


@dataclass(slots=True)
class _ModelRead:
    """A model read on its own, not yet placed in the scope that holds it."""

    entry: WorldModelEntry
    graph: FrameGraph
    pose: Matrix4
    """The model frame's pose in ``relative_to`` (a placement frame already applied)."""
    relative_to: str | None
    """None: the frame of the scope that holds the model."""
    pose_at: SourceLocation | None


class ElementReader:
    """The reader's state and what every element family reads with."""

    def __init__(self, model_paths: ModelPaths, path: str) -> None:
        self.paths = model_paths
        self.path = path
        self.version = "1.6"
        self.warnings: list[str] = []
        self.including: list[str] = []

    def warn(self, where: SourceLocation | None, text: str) -> None:
        self.warnings.append(f"{where or self.path}: warning: {text}")

    @property
    def modern(self) -> bool:
        """SDF 1.7 frame semantics (``relative_to``, ``attached_to``, one namespace)."""
        return _version(self.version) >= (1, 7)

    # --- poses ----------------------------------------------------------------------------------
    def pose(self, parent: Element) -> tuple[Pose, str | None]:
        """The ``<pose>`` of ``parent`` as written and the frame it names (None: the default
        for this kind of element)."""
        el = _child(parent, "pose")
        if el is None:
            return Pose(), None
        relative_to = el.attrs.get("relative_to") or None
        legacy_frame = el.attrs.get("frame") or None
        if legacy_frame is not None and relative_to is None:
            if self.modern:
                self.warn(
                    el.loc,
                    f"<pose frame={legacy_frame!r}> is SDF 1.5/1.6; SDF {self.version} ignores it "
                    "(as Gazebo does): write relative_to",
                )
            else:
                relative_to = legacy_frame
        degrees = el.attrs.get("degrees", "false").strip().lower() in ("1", "true")
        values = _floats(el) or (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)  # <pose relative_to="f"/>
        if el.attrs.get("rotation_format") == "quat_xyzw" or len(values) == 7:
            if len(values) != 7:
                msg = "a quat_xyzw <pose> needs 7 numbers: x y z qx qy qz qw"
                raise SDFError(msg, el.loc)
            rpy = quat_xyzw_to_rpy(*values[3:])
        elif len(values) == 6:
            r, p, y = values[3:6]
            rpy = (math.radians(r), math.radians(p), math.radians(y)) if degrees else (r, p, y)
        else:
            msg = f"<pose> expects 6 numbers (x y z roll pitch yaw), got {len(values)}"
            raise SDFError(msg, el.loc)
        return Pose((values[0], values[1], values[2]), (rpy[0], rpy[1], rpy[2])), relative_to

    def name(self, el: Element, kind: str) -> str:
        """An element's ``name``: present, and (SDF 1.7+) not one SDF reserves."""
        name = el.attrs.get("name", "")
        if not name:
            msg = f"<{el.tag}> needs a name"
            raise SDFError(msg, el.loc)
        if self.modern and (name == "world" or (name.startswith("__") and name.endswith("__"))):
            msg = f"{kind} name {name!r} is reserved in SDF {self.version}"
            raise SDFError(
                msg,
                el.loc,
                hint="'world' and names that start and end with '__' name frames "
                "SDF defines itself",
            )
        if _version(self.version) >= (1, 8) and "::" in name:
            msg = f"{kind} name {name!r} contains '::', which SDF {self.version} keeps for scopes"
            raise SDFError(msg, el.loc)
        return name

    def frame(self, graph: FrameGraph, el: Element, *, scope_frame: str) -> None:
        """An explicit ``<frame>``: attached to ``attached_to`` (default: the scope's frame),
        posed relative to ``relative_to`` (default: what it is attached to)."""
        name = self.name(el, "frame")
        attached = (el.attrs.get("attached_to") if self.modern else None) or scope_frame
        pose, rel = self.pose(el)
        graph.add(
            name,
            "frame",
            pose,
            relative_to=rel or attached,
            attached_to=attached,
            source=_pose_at(el) if rel else el.loc,
        )

    def _frames(self, graph: FrameGraph) -> tuple[WorldFrame, ...]:
        return tuple(
            WorldFrame(name, graph.pose(name), graph.body(name), graph.frames[name].source)
            for name in graph.names("frame")
        )
