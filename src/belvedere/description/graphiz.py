"""A robot's link/joint tree in Graphviz's language, as urdfdom's ``urdf_to_graphiz`` writes
it: links as boxes, joints as blue ellipses, each joint's origin as ``xyz``/``rpy`` on the
edge from its parent link, printed as C++ streams print doubles (six significant digits)."""

from __future__ import annotations

import math

from belvedere.description.urdf import Joint, RobotModel, Vec3

__all__ = ["urdf_to_graphiz"]


def urdf_to_graphiz(model: RobotModel) -> str:
    """The ``.gv`` text ``urdf_to_graphiz`` writes for ``model``: the tree walked from the
    root link depth first, each link's children in the order of their joints' names (urdfdom
    keeps joints in a sorted map)."""
    links: list[str] = []
    joints: list[Joint] = []

    def walk(link: str) -> None:
        links.append(link)
        for joint in sorted(model.child_joints(link), key=lambda j: j.name):
            joints.append(joint)
            walk(joint.child)

    walk(model.root_link.name)
    out = ["digraph G {", "node [shape=box];"]
    out += [f'"{name}" [label="{name}"];' for name in links]
    out.append("node [shape=ellipse, color=blue, fontcolor=blue];")
    for joint in joints:
        roll, pitch, yaw = _urdfdom_rpy(joint.origin.rpy)
        label = f"xyz: {_vector(joint.origin.xyz)} \\nrpy: {_vector((roll, pitch, yaw))}"
        out.append(f'"{joint.parent}" -> "{joint.name}" [label="{label}"]')
        out.append(f'"{joint.name}" -> "{joint.child}"')
    out.append("}")
    return "\n".join(out) + "\n"


def _number(value: float) -> str:
    """A double as ``std::ostream <<`` prints it by default (``%g``)."""
    return f"{value:g}"


def _vector(values: Vec3) -> str:
    return " ".join(_number(v) for v in values)


def _urdfdom_rpy(rpy: Vec3) -> Vec3:
    """The roll, pitch and yaw urdfdom prints: the origin's angles made a unit quaternion and
    read back, so a zero pitch prints as ``-0`` as it does there."""
    half = [a / 2 for a in rpy]
    (sr, sp, sy), (cr, cp, cy) = ([math.sin(h) for h in half], [math.cos(h) for h in half])
    x = sr * cp * cy - cr * sp * sy
    y = cr * sp * cy + sr * cp * sy
    z = cr * cp * sy - sr * sp * cy
    w = cr * cp * cy + sr * sp * sy
    norm = math.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    sine = -2 * (x * z - w * y)
    if sine <= -0.99999:
        return (0.0, -math.pi / 2, 2 * math.atan2(x, -y))
    if sine >= 0.99999:
        return (0.0, math.pi / 2, 2 * math.atan2(-x, y))
    roll = math.atan2(2 * (y * z + w * x), w * w - x * x - y * y + z * z)
    pitch = math.asin(sine)
    yaw = math.atan2(2 * (x * y + w * z), w * w + x * x - y * y - z * z)
    return (roll, pitch, yaw)
