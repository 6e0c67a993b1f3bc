"""A URDF robot as the SDF model Gazebo makes of it when it spawns one (sdformat's URDF
conversion), for a saved world to hold it inline.

As in Gazebo, links joined by fixed joints become one link (the first of them), their
inertias combined about the common centre of mass and their shapes renamed
``LINK_fixed_joint_lump__CHILD_…``; the ``world`` link is dropped and what is fixed to it is
joined to ``world``. ``<gazebo reference>`` friction, contact stiffness, material and gravity
go to the links they name, and so do their sensors (a lumped link's posed in the link it
joins); the robot's own ``<gazebo>`` plugins go to the model. Meshes are written with the
file they resolve to, so the world reads back from any directory.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Mapping
from dataclasses import replace
from pathlib import Path

import numpy as np
import numpy.typing as npt

from belvedere.description.gazebo_materials import gazebo_material_colours
from belvedere.description.meshes import resolve_mesh_path
from belvedere.description.urdf import (
    Box,
    Cylinder,
    Geometry,
    Inertial,
    Link,
    Mesh,
    Pose,
    RobotModel,
    Sphere,
    XmlData,
    transform,
)
from belvedere.errors import SourceLocation
from belvedere.world._model import (
    Material,
    Shape,
    Surface,
    WorldGeometry,
    WorldJoint,
    WorldLink,
    WorldModelEntry,
)
from belvedere.world._poses import from_matrix

__all__ = ["MeshPath", "placed_sensor", "robot_entry"]

logger = logging.getLogger(__name__)

Matrix4 = npt.NDArray[np.float64]
MeshPath = Callable[[Mesh, SourceLocation | None], Path]
"""The file a URDF mesh names (``package://`` resolved)."""

_SDF_JOINT = {"revolute": "revolute", "continuous": "revolute", "prismatic": "prismatic"}


def robot_entry(
    model: RobotModel,
    *,
    name: str,
    pose: Pose = Pose(),
    link_poses: Mapping[str, Matrix4] | None = None,
    mesh_path: MeshPath | None = None,
) -> WorldModelEntry:
    """``model`` as a world model named ``name`` at ``pose`` (the root link's place).

    ``link_poses``: each link's pose in the root link's frame, as the robot stands now
    (default: every joint at 0)."""
    poses = dict(link_poses) if link_poses is not None else model.forward_kinematics()
    resolve = mesh_path or (
        lambda mesh, at: resolve_mesh_path(mesh.filename, relative_to=model.path, requested_at=at)
    )
    convert = _Converter(model, resolve)
    root = model.root_link.name
    starts = [j.child for j in model.child_joints(root)] if root == "world" else [root]
    links: list[WorldLink] = []
    joints: list[WorldJoint] = []
    if root == "world":
        joints += [convert.joint(j.name, "world") for j in model.child_joints(root)]
    while starts:
        start = starts.pop(0)
        members = convert.lumped(start)
        links.append(convert.link(start, members, from_matrix(poses[start])))
        for member, _ in members:
            for j in model.child_joints(member):
                if j.type != "fixed":
                    joints.append(convert.joint(j.name, start))
                    starts.append(j.child)
    robot_wide = model.gazebo_property(None, "static")
    return WorldModelEntry(
        name=name,
        pose=pose,
        static=robot_wide is not None and robot_wide.lower() in ("1", "true"),
        links=tuple(links),
        joints=tuple(joints),
        canonical_link=links[0].name if links else None,
        plugins=tuple(p for g in model.gazebo_for(None) for p in g.plugins),
    )


class _Converter:
    def __init__(self, model: RobotModel, mesh_path: MeshPath) -> None:
        self.model = model
        self.mesh_path = mesh_path

    def prop(self, link: str, key: str) -> str | None:
        return self.model.gazebo_property(link, key)

    def fprop(self, link: str, key: str) -> float | None:
        value = self.prop(link, key)
        try:
            return None if value is None else float(value)
        except ValueError:
            return None  # the simulation refused it when the robot was spawned

    def lumped(self, start: str) -> list[tuple[str, Matrix4]]:
        """``start`` and the links fixed to it, each with its pose in ``start``'s frame."""
        members: list[tuple[str, Matrix4]] = [(start, np.eye(4))]
        stack = [(start, np.eye(4))]
        while stack:
            link, offset = stack.pop()
            for joint in self.model.child_joints(link):
                if joint.type == "fixed":
                    child_offset = offset @ transform(joint.origin)
                    members.append((joint.child, child_offset))
                    stack.append((joint.child, child_offset))
        return members

    def link(self, start: str, members: list[tuple[str, Matrix4]], pose: Pose) -> WorldLink:
        collisions: list[Shape] = []
        visuals: list[Shape] = []
        for name, offset in members:
            link = self.model.link(name)
            collisions += self.collisions(start, link, offset)
            visuals += self.visuals(start, link, offset)
        off = self.prop(start, "turnGravityOff")
        on = self.prop(start, "gravity")
        gravity = not (
            (off is not None and off.lower() in ("1", "true"))
            or (on is not None and on.lower() in ("0", "false"))
        )
        return WorldLink(
            name=start,
            pose=pose,
            inertial=_combined(
                [(lk.inertial, o) for n, o in members if (lk := self.model.link(n)).inertial]
            ),
            collisions=_unique(collisions),
            visuals=_unique(visuals),
            gravity=gravity,
            source=self.model.link(start).source.best,
            sensors=tuple(
                placed_sensor(sensor, offset)
                for name, offset in members
                for ext in self.model.gazebo_for(name)
                for sensor in ext.sensors
            ),
        )

    def collisions(self, start: str, link: Link, offset: Matrix4) -> list[Shape]:
        mu1, mu2 = self.fprop(link.name, "mu1"), self.fprop(link.name, "mu2")
        kp, kd = self.fprop(link.name, "kp"), self.fprop(link.name, "kd")
        surface = None
        if any(v is not None for v in (mu1, mu2, kp, kd)):
            surface = Surface(
                mu=1.0 if mu1 is None else mu1, mu2=1.0 if mu2 is None else mu2, kp=kp, kd=kd
            )
        out: list[Shape] = []
        for c in link.collisions:
            geometry = self.geometry(c.geometry, c.source.best)
            out.append(
                Shape(
                    _shape_name(start, link.name, c.name, "collision"),
                    geometry,
                    from_matrix(offset @ transform(c.origin)),
                    surface=surface,
                    source=c.source.best,
                )
            )
        return out

    def visuals(self, start: str, link: Link, offset: Matrix4) -> list[Shape]:
        named = gazebo_material_colours(self.prop(link.name, "material"))
        materials = {m.name: m for m in self.model.materials}
        out: list[Shape] = []
        for v in link.visuals:
            material: Material | None = None
            if named is not None:  # <gazebo reference><material> wins, as in Gazebo
                material = Material(
                    named.ambient, named.diffuse, named.specular, shininess=named.shininess
                )
            else:
                urdf = v.material if v.material and v.material.rgba else None
                urdf = urdf or materials.get(v.material_name or "")
                if urdf is not None and urdf.rgba is not None:
                    material = Material(urdf.rgba, urdf.rgba)
            out.append(
                Shape(
                    _shape_name(start, link.name, v.name, "visual"),
                    self.geometry(v.geometry, v.source.best),
                    from_matrix(offset @ transform(v.origin)),
                    rgba=material.diffuse if material else None,
                    material=material,
                    source=v.source.best,
                )
            )
        return out

    def geometry(self, geometry: Geometry, at: SourceLocation | None) -> WorldGeometry:
        if isinstance(geometry, Box | Cylinder | Sphere):
            return geometry
        return Mesh(str(self.mesh_path(geometry, at)), geometry.scale)

    def joint(self, name: str, parent: str) -> WorldJoint:
        """An SDF joint from ``parent`` (a lumped link, or ``world``): posed at its child
        link (the URDF joint frame is the child's), its axis in that frame."""
        joint = self.model.joint(name)
        kind = joint.type
        sdf_kind = _SDF_JOINT.get(kind, "fixed")
        if kind not in (*_SDF_JOINT, "fixed"):
            logger.warning(
                "joint %r of robot %r is %s: written as a fixed joint (SDF has no such type)",
                name,
                self.model.name,
                kind,
            )
        lower = upper = effort = velocity = None
        if kind in ("revolute", "prismatic") and joint.limit is not None:
            lower, upper = joint.limit.lower, joint.limit.upper
        if joint.limit is not None and sdf_kind != "fixed":
            effort, velocity = joint.limit.effort, joint.limit.velocity
        dynamics = joint.dynamics
        return WorldJoint(
            name=name,
            type=sdf_kind,
            parent=parent,
            child=joint.child,
            axis=joint.axis if sdf_kind != "fixed" else (0.0, 0.0, 1.0),
            lower=lower,
            upper=upper,
            damping=dynamics.damping if dynamics else 0.0,
            friction=dynamics.friction if dynamics else 0.0,
            source=joint.source.best,
            effort=effort,
            velocity=velocity,
        )


def placed_sensor(sensor: XmlData, offset: Matrix4) -> XmlData:
    """A sensor of a link lumped into another, posed in that one's frame (as sdformat moves
    it); as written if it cannot say where it is (its spawn said why)."""
    if np.array_equal(offset, np.eye(4)):
        return sensor
    written = (sensor.child_text("pose") or "0 0 0 0 0 0").split()
    try:
        x, y, z, roll, pitch, yaw = (float(v) for v in written)
    except ValueError:
        return sensor
    placed = from_matrix(offset @ transform(Pose((x, y, z), (roll, pitch, yaw))))
    text = " ".join(repr(round(v, 12) + 0.0) for v in (*placed.xyz, *placed.rpy))
    rest = tuple(c for c in sensor.children if c.tag != "pose")
    return replace(sensor, children=(XmlData("pose", text=text), *rest))


def _shape_name(start: str, link: str, given: str | None, kind: str) -> str:
    """sdformat's names: ``LINK_collision``, a lumped link's ``START_fixed_joint_lump__…``."""
    base = given or f"{link}_{kind}"
    return base if link == start else f"{start}_fixed_joint_lump__{base}"


def _unique(shapes: list[Shape]) -> tuple[Shape, ...]:
    """Shape names are unique within a link: a repeated one gets ``_1``, ``_2``…"""
    seen: set[str] = set()
    out: list[Shape] = []
    for shape in shapes:
        name, n = shape.name, 0
        while name in seen:
            n += 1
            name = f"{shape.name}_{n}"
        seen.add(name)
        out.append(shape if name == shape.name else _renamed(shape, name))
    return tuple(out)


def _renamed(shape: Shape, name: str) -> Shape:
    return Shape(name, shape.geometry, shape.pose, shape.surface, shape.rgba, shape.material)


def _combined(inertials: list[tuple[Inertial, Matrix4]]) -> Inertial | None:
    """One inertial for lumped links: total mass at the common centre of mass, the tensor
    about it in the first link's axes."""
    if not inertials:
        return None
    if len(inertials) == 1 and np.array_equal(inertials[0][1], np.eye(4)):
        return inertials[0][0]
    total = sum(i.mass for i, _ in inertials)
    if total <= 0:
        return None
    frames = [(i, o @ transform(i.origin)) for i, o in inertials]
    com = sum((i.mass * f[:3, 3] for i, f in frames), np.zeros(3)) / total
    tensor = np.zeros((3, 3))
    for i, f in frames:
        local = np.array([[i.ixx, i.ixy, i.ixz], [i.ixy, i.iyy, i.iyz], [i.ixz, i.iyz, i.izz]])
        r = f[:3, :3]
        d = f[:3, 3] - com
        tensor += r @ local @ r.T + i.mass * (float(d @ d) * np.eye(3) - np.outer(d, d))
    return Inertial(
        mass=total,
        ixx=float(tensor[0, 0]),
        ixy=float(tensor[0, 1]),
        ixz=float(tensor[0, 2]),
        iyy=float(tensor[1, 1]),
        iyz=float(tensor[1, 2]),
        izz=float(tensor[2, 2]),
        origin=Pose((float(com[0]), float(com[1]), float(com[2]))),
    )
