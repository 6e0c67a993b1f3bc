"""A robot saved in a world, read back as the robot it was.

Gazebo saves a robot spawned from URDF as an SDF ``<model>``: its links (those joined by
fixed joints lumped into one), its joints, each link's ``<sensor>``s with their plugins, and
the robot's ``<plugin>``s (the diff drive). Reloading the world runs them again: the robot
drives, publishes odometry and scans as before. :func:`saved_robot` turns such a model back
into a :class:`RobotModel` the simulation spawns as it spawns any robot (a static one, a
camera on a post, fixed to the world).

The URDF frame of each link is its joint's (SDF lets a joint sit anywhere in its child link;
URDF puts the child's frame there): a link whose joint is posed away from it has its
inertial, shapes and sensors moved into the joint's frame.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import numpy.typing as npt

from belvedere.description.urdf import (
    Box,
    Collision,
    Cylinder,
    GazeboExtension,
    Geometry,
    Joint,
    Limit,
    Link,
    Material,
    Mesh,
    Pose,
    RobotModel,
    Source,
    Sphere,
    Visual,
    transform,
)
from belvedere.description.urdf import Dynamics as UrdfDynamics
from belvedere.world._model import SDFError, Shape, WorldJoint, WorldLink, WorldModelEntry
from belvedere.world._poses import from_matrix
from belvedere.world._urdf import placed_sensor

__all__ = ["saved_robot"]

Matrix4 = npt.NDArray[np.float64]

UNBOUNDED = 1e15
"""Limits this far out are none: Gazebo writes a continuous joint as revolute ±1e16."""

_TYPES = {"revolute", "prismatic", "fixed", "continuous"}


def saved_robot(entry: WorldModelEntry) -> tuple[RobotModel, Pose]:
    """The robot a world model with plugins or sensors is, and where its root link goes in
    the world. A static model, or one jointed to ``world``, is a robot fixed to the world
    (a ``world`` link, as URDF has it).

    Raises:
        SDFError: its joints are not a tree of links (URDF needs one) or are of a kind URDF
            has not (ball, universal …).
    """
    parent_joint: dict[str, WorldJoint] = {}
    for joint in entry.joints:
        if joint.type not in _TYPES:
            msg = f"joint {joint.name!r} is {joint.type}, which a URDF robot cannot have"
            raise SDFError(msg, joint.source)
        if joint.child in parent_joint:
            msg = f"link {joint.child!r} is the child of two joints"
            raise SDFError(msg, joint.source)
        parent_joint[joint.child] = joint
    fixed = entry.static or any(j.parent == "world" for j in entry.joints)
    roots = [link.name for link in entry.links if link.name not in parent_joint]
    reached = {*roots, "world"}
    while True:
        more = {j.child for j in entry.joints if j.parent in reached} - reached
        if not more:
            break
        reached |= more
    trees = len(roots) + (1 if fixed and not entry.static else 0)
    if (trees != 1 and not entry.static) or len(reached) != len(entry.links) + 1:
        msg = f"its links are not one tree (roots: {', '.join(roots) or 'none, a loop'})"
        raise SDFError(msg, entry.source)
    # each link's URDF frame in the model frame, and its contents' offset from the SDF link's
    frames: dict[str, Matrix4] = {"world": np.eye(4)}
    offsets: dict[str, Matrix4] = {}
    for link in entry.links:
        parent = parent_joint.get(link.name)
        at_joint: Matrix4 = transform(parent.pose) if parent is not None else np.eye(4)
        frames[link.name] = transform(link.pose) @ at_joint
        offsets[link.name] = np.linalg.inv(at_joint).astype(np.float64)
    joints = [_joint(j, frames[j.parent], frames[j.child]) for j in entry.joints]
    links = []
    extensions = [GazeboExtension(None, plugins=entry.plugins, source=Source(entry.source))]
    if fixed:
        links.append(Link("world"))
        # a static model's trees are welded where they are
        joints += [
            Joint(f"{root}_fixed_to_world", "fixed", "world", root, origin=_pose(frames[root]))
            for root in roots
        ]
    for link in entry.links:
        converted, extension = _link(link, offsets[link.name])
        links.append(converted)
        if extension is not None:
            extensions.append(extension)
    robot = RobotModel(
        name=entry.name,
        links=tuple(links),
        joints=tuple(joints),
        gazebo=tuple(extensions),
        source=Source(entry.source),
    )
    root_frame = frames["world"] if fixed else frames[roots[0]]
    return robot, _pose(transform(entry.pose) @ root_frame)


def _pose(m: Matrix4) -> Pose:
    return from_matrix(m)


def _joint(joint: WorldJoint, parent: Matrix4, child: Matrix4) -> Joint:
    # the SDF axis is in the child link's frame; URDF's in the joint's (the child's new one)
    axis = transform(joint.pose)[:3, :3].T @ np.asarray(joint.axis, dtype=np.float64)
    kind = joint.type
    bounded = (
        joint.lower is not None
        and joint.upper is not None
        and max(abs(joint.lower), abs(joint.upper)) < UNBOUNDED
    )
    if kind == "revolute" and not bounded:
        kind = "continuous"
    limit = None
    if kind != "fixed":
        effort = joint.effort if joint.effort is not None else -1.0
        velocity = joint.velocity if joint.velocity is not None else -1.0
        lower, upper = (joint.lower or 0.0, joint.upper or 0.0) if bounded else (0.0, 0.0)
        limit = Limit(effort, velocity, lower, upper)
    dynamics = None
    if joint.damping or joint.friction:
        dynamics = UrdfDynamics(joint.damping, joint.friction)
    return Joint(
        name=joint.name,
        type=kind,  # type: ignore[arg-type]  # one of _TYPES
        parent=joint.parent,
        child=joint.child,
        origin=_pose(np.linalg.inv(parent) @ child),
        axis=(float(axis[0]), float(axis[1]), float(axis[2])),
        limit=limit,
        dynamics=dynamics,
        source=Source(joint.source),
    )


def _link(link: WorldLink, offset: Matrix4) -> tuple[Link, GazeboExtension | None]:
    """A link in URDF, its contents moved by ``offset``; and its ``<gazebo reference>``:
    friction and stiffness of its first collision with a surface, gravity, sensors."""
    inertial = link.inertial
    if inertial is not None:
        inertial = replace(inertial, origin=_moved(offset, inertial.origin))
    collisions = tuple(
        Collision(geometry, _moved(offset, s.pose), s.name, Source(s.source))
        for s in link.collisions
        if (geometry := _geometry(s)) is not None
    )
    visuals = tuple(
        _visual(link.name, s, geometry, offset)
        for s in link.visuals
        if (geometry := _geometry(s)) is not None
    )
    properties: list[tuple[str, str]] = []
    surface = next((s.surface for s in link.collisions if s.surface is not None), None)
    if surface is not None:
        properties += [("mu1", repr(surface.mu)), ("mu2", repr(surface.mu2))]
        properties += [(k, repr(v)) for k, v in (("kp", surface.kp), ("kd", surface.kd)) if v]
    if not link.gravity:
        properties.append(("gravity", "false"))
    sensors = tuple(placed_sensor(s, offset) for s in link.sensors)
    extension = None
    if properties or sensors:
        extension = GazeboExtension(
            link.name, tuple(properties), sensors=sensors, source=Source(link.source)
        )
    converted = Link(link.name, inertial, visuals, collisions, Source(link.source))
    return converted, extension


def _geometry(shape: Shape) -> Geometry | None:
    """A shape's geometry, if URDF has its kind (planes and polylines it has not)."""
    geometry = shape.geometry
    return geometry if isinstance(geometry, Box | Cylinder | Sphere | Mesh) else None


def _visual(link: str, shape: Shape, geometry: Geometry, offset: Matrix4) -> Visual:
    material = None
    if shape.rgba is not None:
        material = Material(f"{link}::{shape.name}", shape.rgba)
    return Visual(
        geometry,
        _moved(offset, shape.pose),
        shape.name,
        material.name if material else None,
        material,
        Source(shape.source),
    )


def _moved(offset: Matrix4, pose: Pose) -> Pose:
    if np.array_equal(offset, np.eye(4)):
        return pose
    return from_matrix(offset @ transform(pose))
