"""Caster balls welded to what carries them, where that changes nothing the simulation shows.

A caster ball on a continuous joint through its centre costs a degree of freedom, and a body,
at every step. Where its contacts are frictionless (the builder makes caster spheres so) and
nothing else acts on the joint, the joint does no work: a frictionless contact pushes along
the normal, through the sphere's centre, so never about the joint's axis; with no damping or
friction in the joint the ball keeps its spin about that axis (zero, from rest) while its
carrier turns. Welded with that spin's inertia taken out, the carrier then moves exactly as
it does with the joint. The ball looks the same at any angle when its shapes are spheres on
the axis. So a joint is welded only when all of this holds:

* it is ``continuous``, without ``<dynamics>`` damping or friction, and nothing names it: no
  plugin or sensor parameter, no transmission, no mimic, no ``<gazebo reference>``;
* its child is a caster (spheres only, frictionless), with no joints of its own and no
  ``<gazebo>`` block with sensors or plugins;
* every collision and visual of the child is a sphere centred on the axis, and its inertia
  has its centre on the axis and is the same about every direction across it.

Its angle, which nobody publishes, is then always 0.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

import numpy as np
import numpy.typing as npt

from belvedere.description.urdf import (
    Collision,
    Inertial,
    Link,
    RobotModel,
    Sphere,
    Visual,
    XmlData,
    rpy_to_matrix,
)
from belvedere.sim.physics._spec import _tensor_in

__all__ = ["spinning_joints", "without_spin"]

Vector = npt.NDArray[np.float64]

_TOLERANCE = 1e-9
SPIN_KEPT = 1e-6
"""The share of a welded ball's inertia about its axis it keeps."""


def spinning_joints(model: RobotModel, is_caster: Callable[[Link], bool]) -> dict[str, Vector]:
    """The joints to weld (see the module's doc), each with its unit axis in the child link's
    frame. ``is_caster``: whether a link's contacts are frictionless caster spheres."""
    named = _named(model)
    out: dict[str, Vector] = {}
    for joint in model.joints:
        if joint.type != "continuous" or joint.name in named:
            continue
        dynamics = joint.dynamics
        if dynamics is not None and (dynamics.damping != 0 or dynamics.friction != 0):
            continue
        axis = np.asarray(joint.axis, dtype=np.float64)
        norm = float(np.linalg.norm(axis))
        if norm == 0.0:
            continue
        axis = axis / norm
        link = model.link(joint.child)
        if (
            model.child_joints(link.name)
            or any(g.sensors or g.plugins for g in model.gazebo_for(link.name))
            or not is_caster(link)
            or not _spheres_on_axis(link, axis)
            or not _symmetric_about(link.inertial, axis)
        ):
            continue
        out[joint.name] = axis
    return out


def without_spin(tensor: Vector, axis: Vector) -> Vector:
    """An inertia tensor (about the centre of mass) without its part about ``axis`` (a unit
    vector in the same frame): what a ball spinning freely about it adds to its carrier. A
    millionth of that part stays, as MuJoCo refuses a body with a zero principal moment."""
    spin = float(axis @ tensor @ axis)
    result: Vector = tensor - (1.0 - SPIN_KEPT) * spin * np.outer(axis, axis)
    return result


def _named(model: RobotModel) -> set[str]:
    """Every word a plugin, sensor, transmission, mimic or ``<gazebo reference>`` holds."""
    words: set[str] = set()
    for ext in model.gazebo:
        if ext.reference is not None:
            words.add(ext.reference)
        for plugin in ext.plugins:
            for param in plugin.params:
                words.update(_words(param))
        for sensor in ext.sensors:
            words.update(_words(sensor))
    for transmission in model.transmissions:
        words.update(j.name for j in transmission.joints)
    for joint in model.joints:
        if joint.mimic is not None:
            words.update((joint.name, joint.mimic.joint))
    return words


def _words(data: XmlData) -> Iterator[str]:
    yield from data.text.replace(",", " ").split()
    for _, value in data.attrs:
        yield from value.replace(",", " ").split()
    for child in data.children:
        yield from _words(child)


def _point(xyz: tuple[float, float, float]) -> Vector:
    return np.asarray(xyz, dtype=np.float64)


def _on_axis(point: Vector, axis: Vector) -> bool:
    off = point - float(point @ axis) * axis
    return float(np.linalg.norm(off)) <= _TOLERANCE


def _spheres_on_axis(link: Link, axis: Vector) -> bool:
    shapes: list[Collision | Visual] = [*link.collisions, *link.visuals]
    return all(
        isinstance(s.geometry, Sphere) and _on_axis(_point(s.origin.xyz), axis) for s in shapes
    )


def _symmetric_about(inertial: Inertial | None, axis: Vector) -> bool:
    """Centre of mass on the axis, and the same inertia about every direction across it."""
    if inertial is None:
        return True
    if not _on_axis(_point(inertial.origin.xyz), axis):
        return False
    tensor = _tensor_in(inertial, rpy_to_matrix(inertial.origin.rpy))
    across = np.eye(3) - np.outer(axis, axis)
    part = across @ tensor @ across
    level = float(np.trace(part)) / 2.0
    scale = max(float(np.trace(tensor)), 1e-300)
    spin = float(axis @ tensor @ axis)
    leak = tensor @ axis - spin * axis
    return bool(
        np.max(np.abs(part - level * across)) <= _TOLERANCE * scale
        and float(np.linalg.norm(leak)) <= _TOLERANCE * scale
    )
