"""Building a robot's part of the MuJoCo model with ``MjSpec`` from a :class:`RobotModel`
(a :class:`WorldModel`'s part: :mod:`._world_build`; what both use: :mod:`._spec`) — not
through MuJoCo's URDF importer, which welds the base, drops ``<gazebo>`` tags and cannot
read ``.dae`` meshes.

As Gazebo does, links joined by fixed joints are lumped into one body (masses, centres and
inertias combined), so a massless ``base_footprint`` rides on ``base_link``; every URDF link
keeps its offset in its body, so TF still has every frame. Robot geoms win contacts
(``priority``), so the robot's own friction applies as in Gazebo (ODE takes the smaller mu of
the two surfaces; a ground plane's mu of 100 never decides), and caster spheres slide freely.
A caster ball whose joint changes nothing is welded to its carrier (:mod:`._casters`).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np
import numpy.typing as npt

from belvedere.description.gazebo_materials import MaterialColours, gazebo_material_colours
from belvedere.description.meshes import resolve_mesh_path
from belvedere.description.urdf import (
    Geometry,
    Inertial,
    Joint,
    Link,
    Mesh,
    Pose,
    RobotModel,
    Sphere,
    Visual,
    transform,
)
from belvedere.errors import SourceLocation
from belvedere.packages import PackageIndex
from belvedere.sim.physics._casters import spinning_joints, without_spin
from belvedere.sim.physics._lighting import apply_material
from belvedere.sim.physics._spec import (
    Matrix4,
    ModelError,
    Touching,
    _as_collision,
    _as_visual,
    _check_physical,
    _place,
    _tensor_in,
    add_geom,
)
from belvedere.world import Material, Scene

__all__ = ["RobotBuild", "add_robot"]

logger = logging.getLogger("belvedere.physics")

MIN_MASS = 1e-3
"""A moving body with no mass gets this (Gazebo would refuse it less clearly)."""


@dataclass
class RobotBuild:
    """Where a robot went in the spec: each URDF link's body and offset, each joint's name."""

    name: str
    model: RobotModel
    root_body: str
    free_joint: str | None
    link_body: dict[str, tuple[str, Matrix4]] = field(default_factory=dict)
    """URDF link → (MuJoCo body name, T_body_link)."""
    joints: dict[str, str] = field(default_factory=dict)
    """URDF joint → MuJoCo joint name."""
    bodies: list[str] = field(default_factory=list)
    welded: tuple[str, ...] = ()
    """URDF joints welded (caster balls whose joints change nothing, :mod:`._casters`)."""

    def body_of(self, link: str) -> str:
        return self.link_body[link][0]


class _RobotBuilder:
    def __init__(
        self,
        spec: mujoco.MjSpec,
        model: RobotModel,
        name: str,
        packages: PackageIndex | None,
        scene: Scene | None = None,
        *,
        weld_casters: bool = True,
    ) -> None:
        self.spec = spec
        self.scene = scene
        self.model = model
        self.name = name
        self.packages = packages or PackageIndex.from_environment(near=model.path)
        self.materials = {m.name: m for m in model.materials}
        self.meshes: dict[tuple[str, tuple[float, float, float]], str] = {}
        self.spin_axes: dict[str, npt.NDArray[np.float64]] = {}
        """Welded caster links → their joint's axis in the link's frame."""
        if weld_casters:
            for joint, axis in spinning_joints(model, self._is_caster).items():
                self.spin_axes[model.joint(joint).child] = axis

    def prop(self, link: str, key: str) -> str | None:
        return self.model.gazebo_property(link, key)

    def fprop(self, link: str, key: str) -> float | None:
        value = self.prop(link, key)
        if value is None:
            return None
        try:
            return float(value)
        except ValueError:
            at = next((e.source.best for e in self.model.gazebo_for(link)), None)
            msg = f"<gazebo reference={link!r}>: <{key}> expects a number, got {value!r}"
            raise ModelError(msg, at) from None

    def _is_caster(self, link: Link) -> bool:
        return _is_caster(link, self.fprop(link.name, "mu1"), self.fprop(link.name, "mu2"))

    def bprop(self, link: str, key: str) -> bool | None:
        value = self.prop(link, key)
        return None if value is None else value.lower() in ("1", "true")

    def build(self, pose: Pose) -> RobotBuild:
        model = self.model
        root = model.root_link
        fixed_to_world = root.name == "world"
        groups = self._groups(root.name)
        build = RobotBuild(self.name, model, "", None)
        build.welded = tuple(
            j.name for j in model.joints if j.type != "fixed" and j.child in self.spin_axes
        )
        parent_body = self.spec.worldbody
        body = parent_body.add_body(name=f"{self.name}/{root.name}")
        _place(body, transform(pose))
        build.root_body = body.name
        if not fixed_to_world:
            free = body.add_freejoint(name=f"{self.name}/root")
            build.free_joint = free.name
        # A robot fixed to the world (<link name="world"> and a joint to it) keeps its fixed
        # part in a jointless body of its own: welded where it is spawned, and MuJoCo's
        # parent-child contact filter still keeps it from colliding with what it carries.
        self._fill(body, root.name, groups, build, moving=not fixed_to_world)
        return build

    def _groups(self, root: str) -> dict[str, list[tuple[str, Matrix4]]]:
        """For each body-starting link: the links lumped into it with their offsets."""
        groups: dict[str, list[tuple[str, Matrix4]]] = {}
        starts = [root]
        while starts:
            start = starts.pop()
            members = [(start, np.eye(4))]
            stack = [(start, np.eye(4))]
            while stack:
                link, offset = stack.pop()
                for joint in self.model.child_joints(link):
                    if joint.type == "fixed":
                        child_offset = offset @ transform(joint.origin)
                        members.append((joint.child, child_offset))
                        stack.append((joint.child, child_offset))
                    else:
                        starts.append(joint.child)
            groups[start] = members
        return groups

    def _body(
        self,
        parent: mujoco.MjsBody,
        joint: Joint,
        parent_offset: Matrix4,
        groups: dict[str, list[tuple[str, Matrix4]]],
        build: RobotBuild,
    ) -> None:
        body = parent.add_body(name=f"{self.name}/{joint.child}")
        _place(body, parent_offset @ transform(joint.origin))
        if joint.type != "fixed" and joint.child not in self.spin_axes:
            self._joint(body, joint, build)
        self._fill(body, joint.child, groups, build, moving=True)

    def _joint(self, body: mujoco.MjsBody, joint: Joint, build: RobotBuild) -> None:
        axis = np.asarray(joint.axis, dtype=float)
        norm = float(np.linalg.norm(axis))
        if norm == 0.0:
            msg = f"joint {joint.name!r} has a zero axis"
            raise ModelError(msg, joint.source.best)
        axis /= norm
        name = f"{self.name}/{joint.name}"
        dynamics = joint.dynamics
        if joint.type == "planar":
            # two slides in the plane normal to the axis, and a hinge about it
            u = np.cross(axis, [1.0, 0.0, 0.0])
            if np.linalg.norm(u) < 1e-6:
                u = np.cross(axis, [0.0, 1.0, 0.0])
            u /= np.linalg.norm(u)
            v = np.cross(axis, u)
            for suffix, kind, direction in (
                ("x", mujoco.mjtJoint.mjJNT_SLIDE, u),
                ("y", mujoco.mjtJoint.mjJNT_SLIDE, v),
                ("", mujoco.mjtJoint.mjJNT_HINGE, axis),
            ):
                body.add_joint(
                    name=name + (f"_{suffix}" if suffix else ""),
                    type=kind,
                    axis=[float(a) for a in direction],
                )
            build.joints[joint.name] = name
            return
        if joint.type == "floating":
            msg = f"joint {joint.name!r}: floating joints are only possible at the robot's base"
            raise ModelError(msg, joint.source.best)
        kind = (
            mujoco.mjtJoint.mjJNT_SLIDE
            if joint.type == "prismatic"
            else mujoco.mjtJoint.mjJNT_HINGE
        )
        mj = body.add_joint(name=name, type=kind, axis=[float(a) for a in axis])
        if dynamics is not None:
            mj.damping = [dynamics.damping, 0.0, 0.0]  # (MuJoCo 4: a polynomial in velocity)
            mj.frictionloss = dynamics.friction
        limit = joint.limit
        if joint.inverted_limits is not None:
            logger.warning("%s: warning: %s", joint.source, joint.inverted_limits)
        if joint.position_range is not None:
            mj.limited = mujoco.mjtLimited.mjLIMITED_TRUE
            mj.range = list(joint.position_range)
        if limit is not None and limit.effort > 0:
            mj.actfrclimited = mujoco.mjtLimited.mjLIMITED_TRUE
            mj.actfrcrange = [-limit.effort, limit.effort]
        mj.armature = 1e-4  # numerical help for light wheels and fingers
        build.joints[joint.name] = name

    def _fill(
        self,
        body: mujoco.MjsBody,
        start: str,
        groups: dict[str, list[tuple[str, Matrix4]]],
        build: RobotBuild,
        *,
        moving: bool,
    ) -> None:
        build.bodies.append(body.name)
        members = groups[start]
        inertials: list[tuple[Inertial, Matrix4, npt.NDArray[np.float64] | None]] = []
        for link_name, offset in members:
            build.link_body[link_name] = (body.name, offset)
            link = self.model.link(link_name)
            if link.inertial is not None:
                inertials.append((link.inertial, offset, self.spin_axes.get(link_name)))
            self._geoms(body, link, offset)
            if self.bprop(link_name, "turnGravityOff") or self.bprop(link_name, "gravity") is False:
                body.gravcomp = 1.0
        self._inertia(body, start, inertials, moving=moving)
        for link_name, _ in members:
            for joint in self.model.child_joints(link_name):
                if joint.type != "fixed":
                    offset = next(o for n, o in members if n == link_name)
                    self._body(body, joint, offset, groups, build)

    def _inertia(
        self,
        body: mujoco.MjsBody,
        start: str,
        inertials: list[tuple[Inertial, Matrix4, npt.NDArray[np.float64] | None]],
        *,
        moving: bool,
    ) -> None:
        body.explicitinertial = True
        own = self.model.link(start).inertial
        source = (own.source.best if own else None) or self.model.link(start).source.best
        for inertial, _, _ in inertials:
            if inertial.mass < 0:
                msg = f"the mass of link {start!r} is {inertial.mass:g} kg: no body has less than 0"
                raise ModelError(msg, inertial.source.best or source)
        total = sum(i.mass for i, _, _ in inertials)
        if total <= 0:
            if moving:
                logger.warning(
                    "%s: warning: link %r (and the links fixed to it) has no mass; simulating "
                    "it with %g kg",
                    source or self.model.path,
                    start,
                    MIN_MASS,
                )
            body.mass = MIN_MASS
            body.ipos = [0.0, 0.0, 0.0]
            body.fullinertia = [1e-6, 1e-6, 1e-6, 0.0, 0.0, 0.0]
            return
        com = np.zeros(3)
        for inertial, offset, _ in inertials:
            com += inertial.mass * (offset @ transform(inertial.origin))[:3, 3]
        com /= total
        tensor = np.zeros((3, 3))
        for inertial, offset, spin_axis in inertials:
            frame = offset @ transform(inertial.origin)
            d = frame[:3, 3] - com
            part = _tensor_in(inertial, frame[:3, :3])
            if spin_axis is not None:  # a welded caster ball: its spin stays its own
                part = without_spin(part, offset[:3, :3] @ spin_axis)
            tensor += part
            tensor += inertial.mass * (float(d @ d) * np.eye(3) - np.outer(d, d))
        if not np.all(np.isfinite(com)):
            tensor[:] = np.inf  # a centre of mass beyond the doubles: reported as below
        _check_physical(tensor, f"link {start!r} (with the links fixed to it)", source)
        body.mass = total
        body.ipos = [float(v) for v in com]
        body.fullinertia = [
            float(tensor[0, 0]),
            float(tensor[1, 1]),
            float(tensor[2, 2]),
            float(tensor[0, 1]),
            float(tensor[0, 2]),
            float(tensor[1, 2]),
        ]

    # --- geoms ------------------------------------------------------------------------------
    def _geoms(self, body: mujoco.MjsBody, link: Link, offset: Matrix4) -> None:
        mu1 = self.fprop(link.name, "mu1")
        mu2 = self.fprop(link.name, "mu2")
        kp = self.fprop(link.name, "kp")
        kd = self.fprop(link.name, "kd")
        gazebo = gazebo_material_colours(self.prop(link.name, "material"))
        caster = _is_caster(link, mu1, mu2)
        touching = Touching()
        for i, collision in enumerate(link.collisions):
            frame = offset @ transform(collision.origin)
            geom = self._geom(
                body,
                f"{self.name}/{link.name}/collision_{i}",
                collision.geometry,
                frame,
                collision.source.best,
            )
            if geom is None:
                continue
            touching.add(collision.geometry, frame, geom)
            if caster:
                _as_collision(geom, mu=0.0, kp=kp, kd=kd, priority=2, rolling=False)
            else:
                given = [m for m in (mu1, mu2) if m is not None]
                _as_collision(geom, mu=min(given, default=1.0), kp=kp, kd=kd, priority=1)
        for i, visual in enumerate(link.visuals):
            looks = self._looks(visual, gazebo)
            frame = offset @ transform(visual.origin)
            drawn = touching.take(visual.geometry, frame, float(looks.diffuse[3]))
            if drawn is not None:
                apply_material(self.spec, drawn, looks, scene=self.scene)
                continue
            geom = self._geom(
                body,
                f"{self.name}/{link.name}/visual_{i}",
                visual.geometry,
                frame,
                visual.source.best,
            )
            if geom is None:
                continue
            _as_visual(geom)
            apply_material(self.spec, geom, looks, scene=self.scene)

    def _looks(self, visual: Visual, gazebo: MaterialColours | None) -> Material:
        """How a visual is drawn: its ``<gazebo reference><material>`` (which wins, as in
        Gazebo), else its URDF colour as ambient and diffuse (sdformat's conversion)."""
        if gazebo is not None:
            return Material(gazebo.ambient, gazebo.diffuse, gazebo.specular, shininess=1.0)
        material = visual.material
        if material is None or material.rgba is None:
            material = self.materials.get(visual.material_name or "")
        rgba = material.rgba if material and material.rgba else (0.7, 0.7, 0.7, 1.0)
        return Material(rgba, rgba)

    def _geom(
        self,
        body: mujoco.MjsBody,
        name: str,
        geometry: Geometry,
        frame: Matrix4,
        at: SourceLocation | None,
    ) -> mujoco.MjsGeom | None:
        geom = add_geom(self.spec, body, name, geometry, frame, at, self._mesh_file)
        if geom is not None:
            geom.typeinertia = mujoco.mjtGeomInertia.mjINERTIA_VOLUME
        return geom

    def _mesh_file(self, mesh: Mesh, at: SourceLocation | None) -> Path:
        return resolve_mesh_path(
            mesh.filename, relative_to=self.model.path, packages=self.packages, requested_at=at
        )


def _is_caster(link: Link, mu1: float | None, mu2: float | None) -> bool:
    """A caster: spheres only, and called one or given (almost) no friction."""
    spheres = link.collisions and all(isinstance(c.geometry, Sphere) for c in link.collisions)
    frictionless = mu1 is not None and mu2 is not None and max(mu1, mu2) <= 0.01
    return bool(spheres) and ("caster" in link.name.lower() or frictionless)


def add_robot(
    spec: mujoco.MjSpec,
    model: RobotModel,
    *,
    name: str,
    pose: Pose = Pose(),
    packages: PackageIndex | None = None,
    scene: Scene | None = None,
    weld_casters: bool = True,
) -> RobotBuild:
    """Add ``model`` as ``name`` at ``pose`` (its root link's pose in the world), its visuals
    lit as in ``scene`` (default: Gazebo's); ``weld_casters``: weld caster balls whose joints
    change nothing (:mod:`._casters`)."""
    builder = _RobotBuilder(spec, model, name, packages, scene, weld_casters=weld_casters)
    build = builder.build(pose)
    # Gazebo does not collide a model with itself unless <selfCollide> says so.
    self_collide = any(builder.bprop(link.name, "selfCollide") for link in model.links)
    if not self_collide:
        bodies = [b for b in build.bodies if b != "world"]
        for i, a in enumerate(bodies):
            for b in bodies[i + 1 :]:
                spec.add_exclude(bodyname1=a, bodyname2=b)
    return build
