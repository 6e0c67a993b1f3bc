"""Building the MuJoCo model with ``MjSpec`` from a :class:`RobotModel` and a
:class:`WorldModel` — not through MuJoCo's URDF importer, which welds the base, drops
``<gazebo>`` tags and cannot read ``.dae`` meshes.

As Gazebo does, links joined by fixed joints are lumped into one body (masses, centres and
inertias combined), so a massless ``base_footprint`` rides on ``base_link``; every URDF link
keeps its offset in its body, so TF still has every frame. Robot geoms win contacts
(``priority``), so the robot's own friction applies as in Gazebo (ODE takes the smaller mu of
the two surfaces; a ground plane's mu of 100 never decides), and caster spheres slide freely.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np
import numpy.typing as npt

from belvedere.description.gazebo_materials import gazebo_material_colours
from belvedere.description.meshes import load_mesh, resolve_mesh_path
from belvedere.description.urdf import (
    Box,
    Cylinder,
    Geometry,
    Inertial,
    Joint,
    Link,
    Mesh,
    Pose,
    RobotModel,
    Sphere,
    transform,
)
from belvedere.errors import ParseError, SourceLocation
from belvedere.packages import PackageIndex
from belvedere.sim.physics._lighting import apply_material
from belvedere.world import (
    Material,
    Physics,
    Plane,
    Polyline,
    Scene,
    Shape,
    WorldGeometry,
    WorldModel,
)

__all__ = ["ModelError", "RobotBuild", "add_robot", "add_world", "new_spec"]

logger = logging.getLogger("belvedere.physics")

Matrix4 = npt.NDArray[np.float64]

VISUAL_GROUP = 1
COLLISION_GROUP = 3
"""Collision geoms: hit by rays, hidden from cameras (which show VISUAL_GROUP only)."""
MIN_MASS = 1e-3
"""A moving body with no mass gets this (Gazebo would refuse it less clearly)."""


class ModelError(ParseError):
    """A robot or world the physics engine cannot simulate."""


def _quat_wxyz(m: Matrix4) -> list[float]:
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(m[:3, :3]).reshape(9))
    return [float(v) for v in q]


def _place(element: object, m: Matrix4) -> None:
    element.pos = [float(v) for v in m[:3, 3]]  # type: ignore[attr-defined]
    element.quat = _quat_wxyz(m)  # type: ignore[attr-defined]


def new_spec(physics: Physics, *, name: str = "belvedere") -> mujoco.MjSpec:
    spec = mujoco.MjSpec()
    spec.modelname = name
    spec.option.timestep = physics.max_step_size
    spec.option.gravity = list(physics.gravity)
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    # ODE's default friction model is a pyramid too; MuJoCo's pyramid solves ~1.7x faster
    spec.option.cone = mujoco.mjtCone.mjCONE_PYRAMIDAL
    spec.compiler.autolimits = True
    spec.compiler.degree = False  # joint ranges in radians, as URDF has them
    return spec


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
    ) -> None:
        self.spec = spec
        self.scene = scene
        self.model = model
        self.name = name
        self.packages = packages or PackageIndex.from_environment(near=model.path)
        self.materials = {m.name: m for m in model.materials}
        self.meshes: dict[tuple[str, tuple[float, float, float]], str] = {}

    def prop(self, link: str, key: str) -> str | None:
        for ext in self.model.gazebo_for(link):
            value = ext.property(key)
            if value is not None:
                return value.strip()
        return None

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

    def bprop(self, link: str, key: str) -> bool | None:
        value = self.prop(link, key)
        return None if value is None else value.lower() in ("1", "true")

    def build(self, pose: Pose) -> RobotBuild:
        model = self.model
        root = model.root_link
        fixed_to_world = root.name == "world"
        groups = self._groups(root.name)
        build = RobotBuild(self.name, model, "", None)
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
        if joint.type != "fixed":
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
        inertials: list[tuple[Inertial, Matrix4]] = []
        for link_name, offset in members:
            build.link_body[link_name] = (body.name, offset)
            link = self.model.link(link_name)
            if link.inertial is not None:
                inertials.append((link.inertial, offset))
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
        inertials: list[tuple[Inertial, Matrix4]],
        *,
        moving: bool,
    ) -> None:
        body.explicitinertial = True
        own = self.model.link(start).inertial
        source = (own.source.best if own else None) or self.model.link(start).source.best
        for inertial, _ in inertials:
            if inertial.mass < 0:
                msg = f"the mass of link {start!r} is {inertial.mass:g} kg: no body has less than 0"
                raise ModelError(msg, inertial.source.best or source)
        total = sum(i.mass for i, _ in inertials)
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
        for inertial, offset in inertials:
            com += inertial.mass * (offset @ transform(inertial.origin))[:3, 3]
        com /= total
        tensor = np.zeros((3, 3))
        for inertial, offset in inertials:
            frame = offset @ transform(inertial.origin)
            d = frame[:3, 3] - com
            tensor += _tensor_in(inertial, frame[:3, :3])
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
        for i, collision in enumerate(link.collisions):
            geom = self._geom(
                body,
                f"{self.name}/{link.name}/collision_{i}",
                collision.geometry,
                offset @ transform(collision.origin),
                collision.source.best,
            )
            if geom is None:
                continue
            if caster:
                _as_collision(geom, mu=0.0, kp=kp, kd=kd, priority=2, rolling=False)
            else:
                given = [m for m in (mu1, mu2) if m is not None]
                _as_collision(geom, mu=min(given, default=1.0), kp=kp, kd=kd, priority=1)
        for i, visual in enumerate(link.visuals):
            geom = self._geom(
                body,
                f"{self.name}/{link.name}/visual_{i}",
                visual.geometry,
                offset @ transform(visual.origin),
                visual.source.best,
            )
            if geom is None:
                continue
            material = visual.material
            if material is None or material.rgba is None:
                material = self.materials.get(visual.material_name or "")
            if gazebo is not None:  # <gazebo reference><material> wins, as in Gazebo
                looks = Material(gazebo.ambient, gazebo.diffuse, gazebo.specular, shininess=1.0)
            else:  # a URDF colour is ambient and diffuse (sdformat's URDF conversion)
                rgba = material.rgba if material and material.rgba else (0.7, 0.7, 0.7, 1.0)
                looks = Material(rgba, rgba)
            _as_visual(geom)
            apply_material(self.spec, geom, looks, scene=self.scene)

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


def _as_collision(
    geom: mujoco.MjsGeom,
    *,
    mu: float,
    kp: float | None = None,
    kd: float | None = None,
    priority: int = 0,
    rolling: bool = True,
) -> None:
    """A geom that touches things: collision group, friction ``mu`` (with MuJoCo's default
    torsional and rolling friction unless ``rolling`` is off), ODE's kp/kd as a direct
    solref. Not fully transparent: MuJoCo's rays skip geoms with alpha 0."""
    geom.group = COLLISION_GROUP
    geom.rgba = [0.5, 0.5, 0.5, 0.5]
    geom.priority = priority
    geom.friction = [mu, 0.005, 0.0001] if rolling else [mu, 0.0, 0.0]
    # Frictionless: a normal force only. (With friction 0 a pyramidal cone's edges coincide
    # and the contact is degenerate; it is also the cheapest contact.)
    geom.condim = 1 if mu <= 0 else 3
    if kp is not None and kp > 0:
        geom.solref = [-kp, -(kd if kd is not None and kd > 0 else 1.0)]


def _as_visual(geom: mujoco.MjsGeom) -> None:
    """A geom only cameras see: visual group, no contacts, no mass."""
    geom.group = VISUAL_GROUP
    geom.contype = 0
    geom.conaffinity = 0
    geom.mass = 0.0


def _is_caster(link: Link, mu1: float | None, mu2: float | None) -> bool:
    """A caster: spheres only, and called one or given (almost) no friction."""
    spheres = link.collisions and all(isinstance(c.geometry, Sphere) for c in link.collisions)
    frictionless = mu1 is not None and mu2 is not None and max(mu1, mu2) <= 0.01
    return bool(spheres) and ("caster" in link.name.lower() or frictionless)


def add_geom(
    spec: mujoco.MjSpec,
    body: mujoco.MjsBody,
    name: str,
    geometry: Geometry | WorldGeometry,
    frame: Matrix4,
    at: SourceLocation | None,
    mesh_file: Callable[[Mesh, SourceLocation | None], Path],
) -> mujoco.MjsGeom | None:
    """One geom for a URDF or SDF geometry (None for what MuJoCo cannot hold)."""
    geom = body.add_geom(name=name)
    _place(geom, frame)
    if isinstance(geometry, Box):
        geom.type = mujoco.mjtGeom.mjGEOM_BOX
        geom.size = [max(s, 1e-6) / 2 for s in geometry.size]
    elif isinstance(geometry, Cylinder):
        geom.type = mujoco.mjtGeom.mjGEOM_CYLINDER
        geom.size = [max(geometry.radius, 1e-6), max(geometry.length, 1e-6) / 2, 0.0]
    elif isinstance(geometry, Sphere):
        geom.type = mujoco.mjtGeom.mjGEOM_SPHERE
        geom.size = [max(geometry.radius, 1e-6), 0.0, 0.0]
    elif isinstance(geometry, Plane):
        geom.type = mujoco.mjtGeom.mjGEOM_PLANE
        geom.size = [geometry.size[0] / 2, geometry.size[1] / 2, 0.1]
        normal = np.asarray(geometry.normal, dtype=float)
        if np.linalg.norm(normal - [0, 0, 1]) > 1e-9:
            rot = np.eye(4)
            q = np.zeros(4)
            mujoco.mju_quatZ2Vec(q, normal / np.linalg.norm(normal))
            mat = np.zeros(9)
            mujoco.mju_quat2Mat(mat, q)
            rot[:3, :3] = mat.reshape(3, 3)
            _place(geom, frame @ rot)
    elif isinstance(geometry, Polyline):
        vertices = [(x, y, z) for z in (0.0, geometry.height) for x, y in geometry.points]
        mesh_name = f"{name}/polyline"
        spec.add_mesh(name=mesh_name, uservert=[c for v in vertices for c in v])
        geom.type = mujoco.mjtGeom.mjGEOM_MESH
        geom.meshname = mesh_name
    elif isinstance(geometry, Mesh):
        path = mesh_file(geometry, at)
        triangles = load_mesh(path, scale=geometry.scale, requested_at=at)
        mesh_name = f"{name}/mesh"
        spec.add_mesh(
            name=mesh_name,
            uservert=[float(v) for v in triangles.vertices.reshape(-1)],
            userface=[int(f) for f in triangles.faces.reshape(-1)],
        )
        geom.type = mujoco.mjtGeom.mjGEOM_MESH
        geom.meshname = mesh_name
    else:  # pragma: no cover - the geometry union is closed
        spec.delete(geom)
        return None
    return geom


def add_robot(
    spec: mujoco.MjSpec,
    model: RobotModel,
    *,
    name: str,
    pose: Pose = Pose(),
    packages: PackageIndex | None = None,
    scene: Scene | None = None,
) -> RobotBuild:
    """Add ``model`` as ``name`` at ``pose`` (its root link's pose in the world), its visuals
    lit as in ``scene`` (default: Gazebo's)."""
    build = _RobotBuilder(spec, model, name, packages, scene).build(pose)
    # Gazebo does not collide a model with itself unless <selfCollide> says so.
    self_collide = any(
        (v := _prop(model, link.name, "selfCollide")) is not None and v.lower() in ("1", "true")
        for link in model.links
    )
    if not self_collide:
        bodies = [b for b in build.bodies if b != "world"]
        for i, a in enumerate(bodies):
            for b in bodies[i + 1 :]:
                spec.add_exclude(bodyname1=a, bodyname2=b)
    return build


def _prop(model: RobotModel, link: str, key: str) -> str | None:
    for ext in model.gazebo_for(link):
        value = ext.property(key)
        if value is not None:
            return value.strip()
    return None


def add_world(
    spec: mujoco.MjSpec, world: WorldModel, *, scene: Scene | None = None
) -> dict[str, str]:
    """Every model of the world: static ones welded to the world body, others one free rigid
    body per model (its first link, the others fixed to it). Returns model → root body.
    Visuals are lit as in ``scene`` (default: the world's)."""
    scene = scene or world.scene
    roots: dict[str, str] = {}
    for model in world.models:
        if model.joints:
            logger.warning(
                "model %r: its %d joints are simulated as rigid (joints between the links of "
                "world models are not supported yet)",
                model.name,
                len(model.joints),
            )
        root: mujoco.MjsBody | None = None
        root_from_model = np.eye(4)
        for link in model.links:
            model_from_link = transform(link.pose)
            if model.static:
                body = spec.worldbody
                frame = transform(model.pose) @ model_from_link
            elif root is None:
                root = body = spec.worldbody.add_body(name=f"{model.name}/{link.name}")
                _place(body, transform(model.pose) @ model_from_link)
                body.add_freejoint(name=f"{model.name}/free")
                root_from_model = np.asarray(np.linalg.inv(model_from_link), dtype=np.float64)
                frame = np.eye(4)
            else:
                body = root.add_body(name=f"{model.name}/{link.name}")
                _place(body, root_from_model @ model_from_link)
                frame = np.eye(4)
            if not model.static:
                what = f"link {link.name!r} of model {model.name!r}"
                _world_inertia(body, link.inertial, what, link.source)
                if not link.gravity:
                    body.gravcomp = 1.0
            roots.setdefault(
                model.name, "world" if model.static else str(root.name if root else "")
            )
            for kind, shapes in (("collision", link.collisions), ("visual", link.visuals)):
                for i, shape in enumerate(shapes):
                    name = f"{model.name}/{link.name}/{kind}_{i}"
                    _world_shape(
                        spec, body, name, shape, frame, visual=kind == "visual", scene=scene
                    )
    return roots


def _check_physical(
    tensor: npt.NDArray[np.float64], what: str, source: SourceLocation | None
) -> None:
    """MuJoCo refuses (or diverges on) principal moments no body has."""
    if not np.all(np.isfinite(tensor)):
        msg = f"the inertia of {what} overflows a double"
        raise ModelError(msg, source, hint="check its <mass> and <inertia> values")
    eigen = np.linalg.eigvalsh(tensor)
    if eigen[0] <= 0 or eigen[0] + eigen[1] < eigen[2] * (1 - 1e-6):
        msg = (
            f"the inertia of {what} is not physical: principal moments "
            f"{', '.join(f'{e:.6g}' for e in eigen)} must be positive and no one larger than "
            "the sum of the other two"
        )
        raise ModelError(msg, source, hint="check its <inertia> ixx/iyy/izz values")


def _tensor_in(inertial: Inertial, rotation: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """The inertia tensor about the centre of mass, in the frame ``rotation`` maps from."""
    local = np.array(
        [
            [inertial.ixx, inertial.ixy, inertial.ixz],
            [inertial.ixy, inertial.iyy, inertial.iyz],
            [inertial.ixz, inertial.iyz, inertial.izz],
        ]
    )
    result: npt.NDArray[np.float64] = rotation @ local @ rotation.T
    return result


def _world_inertia(
    body: mujoco.MjsBody, inertial: Inertial | None, what: str, source: SourceLocation | None
) -> None:
    body.explicitinertial = True
    if inertial is None:
        body.mass = 1.0
        body.fullinertia = [0.01, 0.01, 0.01, 0.0, 0.0, 0.0]
        return
    o = transform(inertial.origin)
    body.mass = inertial.mass
    body.ipos = [float(v) for v in o[:3, 3]]
    t = _tensor_in(inertial, o[:3, :3])
    _check_physical(t, what, source)
    body.fullinertia = [t[0, 0], t[1, 1], t[2, 2], t[0, 1], t[0, 2], t[1, 2]]


def _world_shape(
    spec: mujoco.MjSpec,
    body: mujoco.MjsBody,
    name: str,
    shape: Shape,
    frame: Matrix4,
    *,
    visual: bool,
    scene: Scene,
) -> None:
    def mesh_file(mesh: Mesh, at: SourceLocation | None) -> Path:
        return Path(mesh.filename)

    geom = add_geom(
        spec, body, name, shape.geometry, frame @ transform(shape.pose), shape.source, mesh_file
    )
    if geom is None:
        return
    geom.typeinertia = mujoco.mjtGeomInertia.mjINERTIA_VOLUME
    if visual:
        _as_visual(geom)
        material = shape.material
        if material is None:
            rgba = shape.rgba or (0.75, 0.75, 0.75, 1.0)
            material = Material(rgba, rgba)
        apply_material(spec, geom, material, scene=scene)
        return
    # A moving model's own friction decides against the static world (the ground's mu 100
    # would otherwise win: MuJoCo takes the larger of two equal-priority geoms', ODE the smaller)
    priority = 0 if body.name == "world" else 1
    surface = shape.surface
    if surface is None:
        _as_collision(geom, mu=1.0, priority=priority)
    else:
        mu = min(surface.mu, surface.mu2)
        _as_collision(geom, mu=mu, kp=surface.kp, kd=surface.kd, priority=priority)
