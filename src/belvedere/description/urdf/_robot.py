"""``RobotModel``: the whole robot, its tree, and forward kinematics."""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
import numpy.typing as npt

from belvedere.bounded import TEXT_FILE_BYTES, LimitError, read_regular
from belvedere.description.urdf._model import (
    GazeboExtension,
    Joint,
    Link,
    Material,
    Pose,
    Source,
    Transmission,
    Vec3,
)
from belvedere.description.urdf._parse import Diagnostic, ParsedRobot, parse_robot
from belvedere.description.urdf._write import write_urdf
from belvedere.errors import ParseError
from belvedere.xmldom import Element, check_depth, parse_file, parse_string

__all__ = ["RobotModel", "URDFError", "load_robot", "rpy_to_matrix", "transform"]

Matrix4 = npt.NDArray[np.float64]


class URDFError(ParseError):
    """A URDF that urdfdom (and so ROS) would reject."""


def rpy_to_matrix(rpy: Vec3) -> npt.NDArray[np.float64]:
    """URDF's fixed-axis roll, pitch, yaw (about x, then y, then z) as a 3x3 rotation."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = (
        math.cos(r),
        math.sin(r),
        math.cos(p),
        math.sin(p),
        math.cos(y),
        math.sin(y),
    )
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def transform(pose: Pose) -> Matrix4:
    """The 4x4 homogeneous transform of an ``<origin>``."""
    t = np.eye(4)
    t[:3, :3] = rpy_to_matrix(pose.rpy)
    t[:3, 3] = pose.xyz
    return t


def _axis_angle(axis: Vec3, angle: float) -> npt.NDArray[np.float64]:
    a = np.asarray(axis, dtype=float)
    norm = float(np.linalg.norm(a))
    if norm == 0.0:
        return np.eye(3)
    x, y, z = a / norm
    c, s = math.cos(angle), math.sin(angle)
    k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    rotation: npt.NDArray[np.float64] = np.eye(3) + s * k + (1.0 - c) * (k @ k)
    return rotation


@dataclass(frozen=True)
class RobotModel:
    """A robot description. Build it with :meth:`from_path` or :meth:`from_string`."""

    name: str
    links: tuple[Link, ...]
    joints: tuple[Joint, ...] = ()
    materials: tuple[Material, ...] = ()
    transmissions: tuple[Transmission, ...] = ()
    gazebo: tuple[GazeboExtension, ...] = ()
    source: Source = field(default_factory=Source, compare=False, repr=False)
    warnings: tuple[Diagnostic, ...] = field(default=(), compare=False, repr=False)
    """What urdfdom would log but accept (dropped visuals, colourless materials…)."""
    path: str | None = field(default=None, compare=False, repr=False)
    """The file it was read from (relative mesh paths resolve against its directory)."""

    # --- construction --------------------------------------------------------------------------
    @classmethod
    def from_string(cls, text: str | bytes, *, path: str = "<string>") -> RobotModel:
        """Parse URDF text."""
        return cls.from_parsed(
            parse_robot(parse_string(text, path, namespaces=False, keep_blank=False))
        )

    @classmethod
    def from_path(
        cls,
        path: str | os.PathLike[str],
        *,
        mappings: dict[str, str] | None = None,
        **xacro_options: Any,
    ) -> RobotModel:
        """Read a URDF file, or expand a xacro file first (``.xacro``, or a file declaring the
        xacro namespace). ``mappings`` and other options go to xacro."""
        return cls.from_parsed(load_robot(path, mappings=mappings, **xacro_options))

    @classmethod
    def from_parsed(cls, parsed: ParsedRobot) -> RobotModel:
        """The model of a parse without errors (raises the first error otherwise)."""
        errors = [d for d in parsed.diagnostics if d.severity == "error"]
        if errors:
            first = errors[0]
            raise URDFError(first.message, first.location)
        return cls(
            parsed.name,
            tuple(parsed.links),
            tuple(parsed.joints),
            tuple(parsed.materials),
            tuple(parsed.transmissions),
            tuple(parsed.gazebo),
            parsed.source,
            tuple(parsed.diagnostics),
            parsed.path,
        )

    def to_urdf(self) -> str:
        """URDF text for this model (parsing it gives an equal model)."""
        return write_urdf(
            self.name,
            materials=self.materials,
            links=self.links,
            joints=self.joints,
            transmissions=self.transmissions,
            gazebo=self.gazebo,
        )

    # --- lookups -------------------------------------------------------------------------------
    @cached_property
    def _links(self) -> dict[str, Link]:
        return {link.name: link for link in self.links}

    @cached_property
    def _joints(self) -> dict[str, Joint]:
        return {j.name: j for j in self.joints}

    @cached_property
    def _parent_joint(self) -> dict[str, Joint]:
        return {j.child: j for j in sorted(self.joints, key=lambda j: j.name)}

    @cached_property
    def _child_joints(self) -> dict[str, tuple[Joint, ...]]:
        out: dict[str, list[Joint]] = {}
        for j in sorted(self.joints, key=lambda j: j.name):
            out.setdefault(j.parent, []).append(j)
        return {k: tuple(v) for k, v in out.items()}

    def link(self, name: str) -> Link:
        try:
            return self._links[name]
        except KeyError:
            msg = f"no link {name!r} in robot {self.name!r}"
            raise KeyError(msg) from None

    def joint(self, name: str) -> Joint:
        try:
            return self._joints[name]
        except KeyError:
            msg = f"no joint {name!r} in robot {self.name!r}"
            raise KeyError(msg) from None

    @cached_property
    def root_link(self) -> Link:
        """The one link no joint has as its child."""
        roots = [link for link in sorted(self._links) if link not in self._parent_joint]
        return self._links[roots[0]]

    def parent_joint(self, link: str) -> Joint | None:
        return self._parent_joint.get(link)

    def parent_link(self, link: str) -> str | None:
        j = self._parent_joint.get(link)
        return j.parent if j else None

    def child_joints(self, link: str) -> tuple[Joint, ...]:
        """Joints whose parent is ``link``, ordered by joint name (as urdfdom orders them)."""
        return self._child_joints.get(link, ())

    def children(self, link: str) -> tuple[str, ...]:
        return tuple(j.child for j in self.child_joints(link))

    @property
    def movable_joints(self) -> tuple[Joint, ...]:
        """Joints that move (not fixed), in document order."""
        return tuple(j for j in self.joints if j.movable)

    def chain(self, start: str, end: str) -> tuple[Joint, ...]:
        """The joints from link ``start`` to link ``end``: up to their common ancestor, then
        down (joints on the way up are traversed against their direction)."""
        up, down = self._path_to_root(start), self._path_to_root(end)
        up_links = [start] + [j.parent for j in up]
        down_links = [end] + [j.parent for j in down]
        common = next((link for link in up_links if link in down_links), None)
        if common is None:
            msg = f"links {start!r} and {end!r} are not connected"
            raise ValueError(msg)
        rising = up[: up_links.index(common)]
        falling = down[: down_links.index(common)]
        return (*rising, *reversed(falling))

    def _path_to_root(self, link: str) -> list[Joint]:
        self.link(link)
        path: list[Joint] = []
        seen = {link}
        j = self._parent_joint.get(link)
        while j is not None and j.parent not in seen:
            path.append(j)
            seen.add(j.parent)
            j = self._parent_joint.get(j.parent)
        return path

    # --- kinematics ----------------------------------------------------------------------------
    def joint_transform(self, joint: Joint, q: float = 0.0) -> Matrix4:
        """parent link → child link at the joint's own position ``q`` (for a mimic joint,
        its own value: ``multiplier * leader + offset``, as joint_states carry it). Revolute
        and prismatic joints turn about and move along their axis made unit length, as KDL
        does."""
        t = transform(joint.origin)
        if joint.type in ("revolute", "continuous"):
            motion = np.eye(4)
            motion[:3, :3] = _axis_angle(joint.axis, q)
            return t @ motion
        if joint.type == "prismatic":
            # KDL (and so robot_state_publisher) moves along the unit axis, whatever its length
            axis = np.asarray(joint.axis, dtype=float)
            norm = float(np.linalg.norm(axis))
            motion = np.eye(4)
            if norm != 0.0:
                motion[:3, 3] = axis / norm * q
            return t @ motion
        return t

    def forward_kinematics(
        self, positions: Mapping[str, float] | None = None
    ) -> dict[str, Matrix4]:
        """Pose of every link in the root link's frame (4x4), for joint positions by name.

        Missing joints are at 0; a mimic joint follows the joint it mimics.
        """
        q = dict(positions or {})
        poses: dict[str, Matrix4] = {self.root_link.name: np.eye(4)}
        stack = [self.root_link.name]
        while stack:
            parent = stack.pop()
            for j in self.child_joints(parent):
                if j.child in poses:
                    continue  # a cycle or a second parent: keep the first pose found
                if j.mimic is not None:
                    value = j.mimic.multiplier * q.get(j.mimic.joint, 0.0) + j.mimic.offset
                else:
                    value = q.get(j.name, 0.0)
                poses[j.child] = poses[parent] @ self.joint_transform(j, value)
                stack.append(j.child)
        return poses

    # --- extensions ----------------------------------------------------------------------------
    def gazebo_for(self, reference: str | None) -> tuple[GazeboExtension, ...]:
        """``<gazebo>`` blocks for a link or joint (None: robot-wide)."""
        return tuple(g for g in self.gazebo if g.reference == reference)

    def gazebo_property(self, reference: str | None, key: str) -> str | None:
        """The first ``<key>`` of the ``<gazebo>`` blocks for a link or joint (None:
        robot-wide), without the white space around it, as Gazebo reads it."""
        for ext in self.gazebo_for(reference):
            value = ext.property(key)
            if value is not None:
                return value.strip()
        return None


def load_robot(
    path: str | os.PathLike[str], *, mappings: dict[str, str] | None = None, **xacro_options: Any
) -> ParsedRobot:
    """Parse a URDF file, or expand a xacro file and parse the result, keeping every
    diagnostic (xacro's warnings first) instead of raising on urdfdom's errors."""
    name = os.fspath(path)
    if not _is_xacro(name):
        parsed = parse_robot(parse_file(name, namespaces=False, keep_blank=False))
        parsed.path = name
        return parsed
    from belvedere.description.xacro import expand_file

    expansion = expand_file(name, mappings=mappings, on_warning=lambda _: None, **xacro_options)
    check_depth(expansion.document)  # here, where elements still know their xacro lines
    text = expansion.to_xml()
    urdf = parse_string(text, f"{name} (expanded)", namespaces=False, keep_blank=False)
    # The printed URDF has the expanded tree's elements in the same order: pair them up so
    # each part knows the xacro line that produced it.
    origin = dict(
        zip(
            (id(e) for e in _walk(urdf.root)),
            (e.loc for e in _walk(expansion.document.root)),
            strict=True,
        )
    )
    parsed = parse_robot(urdf, xacro_location=lambda el: origin.get(id(el)))
    parsed.diagnostics[:0] = [
        Diagnostic("warning", w.message, w.location, w.legacy) for w in expansion.warnings
    ]
    parsed.path = name
    return parsed


def _is_xacro(path: str) -> bool:
    """A ``.xacro`` file, or any other file that uses xacro tags (URDF output never does,
    though ROS 1 xacro left ``xmlns:xacro`` on it)."""
    if path.endswith(".xacro"):
        return True
    try:
        return b"<xacro:" in read_regular(path, limit=TEXT_FILE_BYTES)
    except LimitError:
        return False  # not a file to read: parse_file says why


def _walk(root: Element) -> list[Element]:
    out: list[Element] = []
    stack = [root]
    while stack:
        el = stack.pop()
        out.append(el)
        stack.extend(reversed(list(el.elements())))
    return out
