"""A :class:`WorldModel`'s models in the spec: static ones welded to the world body, others
one free rigid body each, with their inertia, collision and visual geoms."""

from __future__ import annotations

import logging
from pathlib import Path

import mujoco
import numpy as np

from belvedere.description.urdf import Inertial, Mesh, transform
from belvedere.errors import SourceLocation
from belvedere.sim.physics._lighting import apply_material
from belvedere.sim.physics._spec import (
    Matrix4,
    Touching,
    _as_collision,
    _as_visual,
    _check_physical,
    _place,
    _tensor_in,
    add_geom,
)
from belvedere.world import Material, Scene, Shape, WorldModel

__all__ = ["add_world"]

logger = logging.getLogger("belvedere.physics")


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
            touching = Touching()
            for kind, shapes in (("collision", link.collisions), ("visual", link.visuals)):
                for i, shape in enumerate(shapes):
                    name = f"{model.name}/{link.name}/{kind}_{i}"
                    _world_shape(
                        spec,
                        body,
                        name,
                        shape,
                        frame,
                        touching,
                        visual=kind == "visual",
                        scene=scene,
                    )
    return roots


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
    touching: Touching,
    *,
    visual: bool,
    scene: Scene,
) -> None:
    def mesh_file(mesh: Mesh, at: SourceLocation | None) -> Path:
        return Path(mesh.filename)

    at = frame @ transform(shape.pose)
    rgba = shape.rgba or (0.75, 0.75, 0.75, 1.0)
    looks = shape.material or Material(rgba, rgba)
    if visual:
        drawn = touching.take(shape.geometry, at, float(looks.diffuse[3]))
        if drawn is not None:
            apply_material(spec, drawn, looks, scene=scene)
            return
    geom = add_geom(spec, body, name, shape.geometry, at, shape.source, mesh_file)
    if geom is None:
        return
    geom.typeinertia = mujoco.mjtGeomInertia.mjINERTIA_VOLUME
    if visual:
        _as_visual(geom)
        apply_material(spec, geom, looks, scene=scene)
        return
    touching.add(shape.geometry, at, geom)
    # A moving model's own friction decides against the static world (the ground's mu 100
    # would otherwise win: MuJoCo takes the larger of two equal-priority geoms', ODE the smaller)
    priority = 0 if body.name == "world" else 1
    surface = shape.surface
    if surface is None:
        _as_collision(geom, mu=1.0, priority=priority)
    else:
        mu = min(surface.mu, surface.mu2)
        _as_collision(geom, mu=mu, kp=surface.kp, kd=surface.kd, priority=priority)
