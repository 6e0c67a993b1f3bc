"""The pieces an ``MjSpec`` is built from, for robots and world models alike: the spec and
its options, placing elements, geoms for URDF and SDF geometry (collision or visual), the
checks on inertia, and the error for what the engine cannot simulate."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import mujoco
import numpy as np
import numpy.typing as npt

from belvedere.description.meshes import load_mesh
from belvedere.description.urdf import Box, Cylinder, Geometry, Inertial, Mesh, Sphere
from belvedere.errors import ParseError, SourceLocation
from belvedere.world import Physics, Plane, Polyline, WorldGeometry

__all__ = [
    "COLLISION_GROUP",
    "DRAWN_GROUP",
    "VISUAL_GROUP",
    "Matrix4",
    "ModelError",
    "Touching",
    "add_geom",
    "new_spec",
]

Matrix4 = npt.NDArray[np.float64]

VISUAL_GROUP = 1
"""Geoms only cameras see (no contacts, no rays)."""
DRAWN_GROUP = 2
"""Collision geoms that are their visual too (the same shape at the same place): they touch,
rays hit them and cameras draw them. A visual that needs no geom of its own costs the
physics nothing at every step (MuJoCo places every geom, and weighs every pair of geoms of
two bodies that come near, contacts or not)."""
COLLISION_GROUP = 3
"""Collision geoms: hit by rays, hidden from cameras (which show VISUAL_GROUP and
DRAWN_GROUP)."""
CAMERA_GROUPS = (VISUAL_GROUP, DRAWN_GROUP)
RAY_GROUPS = (DRAWN_GROUP, COLLISION_GROUP)


class ModelError(ParseError):
    """A robot or world the physics engine cannot simulate."""


class Touching:
    """A link's collision geoms as they are added, for its visuals to find the one that can
    be drawn in their place: the same geometry at exactly the same frame, drawn with an
    opaque enough colour (MuJoCo's rays skip a geom whose alpha is 0)."""

    def __init__(self) -> None:
        self._geoms: list[tuple[object, Matrix4, mujoco.MjsGeom]] = []

    def add(self, geometry: object, frame: Matrix4, geom: mujoco.MjsGeom) -> None:
        self._geoms.append((geometry, frame, geom))

    def take(self, geometry: object, frame: Matrix4, alpha: float) -> mujoco.MjsGeom | None:
        """The collision geom to draw for a visual of ``geometry`` at ``frame`` (then no longer
        offered to another visual), or None: the visual needs a geom of its own."""
        if alpha <= 0.0:
            return None
        for i, (shape, at, geom) in enumerate(self._geoms):
            if shape == geometry and np.array_equal(at, frame):
                del self._geoms[i]
                geom.group = DRAWN_GROUP
                return geom
        return None


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
