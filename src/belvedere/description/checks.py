"""``belvedere check``: urdfdom's verdict on a robot, its tree, and a physics-readiness lint.

The verdict and the tree printout are ``check_urdf``'s. The lint adds warnings (file:line)
for what makes a model misbehave in a simulator: missing or impossible inertia, visuals with
nothing to collide, meshes that do not resolve, inverted joint limits, a diff-drive plugin
whose wheels are swapped, Gazebo blocks for links that do not exist.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Any, Final

import numpy as np

from belvedere.description.meshes import resolve_mesh_path
from belvedere.description.urdf import (
    Collision,
    Diagnostic,
    Inertial,
    Mesh,
    RobotModel,
    Source,
    Visual,
    load_robot,
)
from belvedere.errors import BelvedereError, ParseError
from belvedere.packages import PackageIndex

__all__ = ["CheckReport", "check_file", "format_tree", "lint"]

DIFF_DRIVE_PLUGINS: Final = ("libgazebo_ros_diff_drive.so", "gazebo_ros_diff_drive")
AXIS_LENGTH_TOLERANCE: Final = 1e-3
"""How far from 1 an axis's length may be before ``check`` warns (``0.707 0 0.707`` is unit
enough; ``0 0 2`` is not)."""


@dataclass
class CheckReport:
    """The outcome of checking one file."""

    path: str
    model: RobotModel | None
    diagnostics: list[Diagnostic] = field(default_factory=list)
    failure: ParseError | None = None
    """Why the file could not be read or expanded at all (a missing file, malformed XML, a
    xacro error): the one error, with the macro and include trail and hint it carries."""

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity == "error"]

    @property
    def warnings(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity == "warning"]

    @property
    def notes(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity == "note"]

    @property
    def ok(self) -> bool:
        """urdfdom's verdict: the file parses into a robot."""
        return self.model is not None and not self.errors

    def to_json(self) -> dict[str, Any]:
        def diag(d: Diagnostic) -> dict[str, Any]:
            loc = d.location
            out: dict[str, Any] = {
                "severity": d.severity,
                "message": d.message,
                "file": loc.path if loc else None,
                "line": loc.line if loc else None,
                "column": loc.col if loc else None,
            }
            if self.failure is not None:  # the only diagnostic then
                out["trail"] = [f"{t.what} {t.location}" for t in self.failure.trail]
                out["hint"] = self.failure.hint
            return out

        out: dict[str, Any] = {
            "file": self.path,
            "ok": self.ok,
            "errors": len(self.errors),
            "warnings": len(self.warnings),
            "diagnostics": [diag(d) for d in self.diagnostics],
        }
        if self.model is not None:
            m = self.model
            out["robot"] = m.name
            out["root"] = m.root_link.name
            out["links"] = [link.name for link in m.links]
            out["joints"] = [{"name": j.name, "type": j.type} for j in m.joints]
            out["tree"] = _tree_json(m, m.root_link.name, set())
        return out


def _tree_json(model: RobotModel, link: str, seen: set[str]) -> dict[str, Any]:
    seen.add(link)
    return {
        "link": link,
        "children": [
            {"joint": j.name, **_tree_json(model, j.child, seen)}
            for j in model.child_joints(link)
            if j.child not in seen
        ],
    }


def format_tree(model: RobotModel) -> str:
    """The robot as ``check_urdf`` prints it."""
    lines = [
        f"robot name is: {model.name}",
        "---------- Successfully Parsed XML ---------------",
    ]
    root = model.root_link.name
    lines.append(f"root Link: {root} has {len(model.children(root))} child(ren)")

    def walk(link: str, level: int, seen: frozenset[str]) -> None:
        level += 2
        for count, child in enumerate(model.children(link), start=1):
            lines.append("  " * level + f"child({count}):  {child}")
            if child not in seen:  # urdfdom would recurse forever on a reachable cycle
                walk(child, level, seen | {child})

    walk(root, 0, frozenset({root}))
    return "\n".join(lines) + "\n"


def check_file(
    path: str | os.PathLike[str],
    *,
    mappings: dict[str, str] | None = None,
    packages: PackageIndex | None = None,
    simulated: bool | None = None,
    **xacro_options: Any,
) -> CheckReport:
    """Check a URDF or xacro file. ``simulated`` (default: when the model has Gazebo or
    transmission elements) enables the warnings that only matter in a simulator."""
    name = os.fspath(path)
    try:
        parsed = load_robot(name, mappings=mappings, packages=packages, **xacro_options)
    except ParseError as err:  # not even XML, or xacro failed: one error, where it is
        return CheckReport(name, None, [Diagnostic("error", err.message, err.location)], err)
    report = CheckReport(name, None, list(parsed.diagnostics))
    _hint_zero_links(report)
    if parsed.fatal:
        return report
    model = RobotModel.from_parsed(parsed)
    report.model = model
    report.diagnostics.extend(
        d
        for d in lint(model, packages=packages, simulated=simulated)
        if d not in report.diagnostics
    )
    return report


def _hint_zero_links(report: CheckReport) -> None:
    for i, d in enumerate(report.diagnostics):
        if d.severity == "error" and d.message.startswith("no link elements"):
            report.diagnostics[i] = Diagnostic(
                "error",
                f"{d.message}: the xacro probably uses legacy macro calls (<wheel/> instead "
                "of <xacro:wheel/>); try --dialect melodic, or the default --dialect auto",
                d.location,
            )


def lint(
    model: RobotModel,
    *,
    packages: PackageIndex | None = None,
    simulated: bool | None = None,
) -> list[Diagnostic]:
    """Physics-readiness warnings for a parsed model."""
    if simulated is None:
        simulated = bool(model.gazebo or model.transmissions)
    out: list[Diagnostic] = []

    def warn(message: str, source: Source | None) -> None:
        out.append(Diagnostic("warning", message, source.best if source else None))

    movable_children = {j.child for j in model.joints if j.movable}
    for link in model.links:
        if link.inertial is None:
            if simulated and (link.collisions or link.name in movable_children):
                warn(
                    f"link '{link.name}' has no <inertial>: simulators drop it (and its "
                    "collisions) or give it no mass",
                    link.source,
                )
        else:
            for message in _inertia_problems(link.inertial):
                warn(f"link '{link.name}': {message}", link.inertial.source)
        if link.visuals and not link.collisions and link.inertial is not None and simulated:
            warn(
                f"link '{link.name}' has a visual but no collision: it will pass through "
                "things in simulation",
                link.source,
            )
        parts: tuple[Visual | Collision, ...] = (*link.visuals, *link.collisions)
        for part in parts:
            if isinstance(part.geometry, Mesh):
                try:
                    file = resolve_mesh_path(
                        part.geometry.filename,
                        relative_to=model.path,
                        packages=packages,
                        requested_at=part.source.best,
                    )
                except BelvedereError as err:
                    warn(
                        f"mesh {part.geometry.filename!r} does not resolve: {err.message}",
                        part.source,
                    )
                    continue
                if not os.path.isfile(file):
                    warn(
                        f"mesh {part.geometry.filename!r} does not resolve: no file {file}",
                        part.source,
                    )

    for j in model.joints:
        inverted = j.inverted_limits
        if inverted is not None:
            warn(inverted, j.source)
        if j.type not in ("fixed", "floating") and j.axis == (0.0, 0.0, 0.0):
            warn(f"joint '{j.name}' has a zero axis (<axis> without xyz)", j.source)
        elif j.type in ("revolute", "continuous", "prismatic"):
            length = math.sqrt(sum(c * c for c in j.axis))
            if abs(length - 1.0) > AXIS_LENGTH_TOLERANCE:
                unit = " ".join(f"{c / length:.6g}" for c in j.axis)
                warn(
                    f"joint '{j.name}': axis {' '.join(f'{c:g}' for c in j.axis)} has length "
                    f"{length:.6g}, not 1: robot_state_publisher (KDL) and simulators use the "
                    f"unit axis {unit}, so a {j.type} joint at q "
                    f"{'moves q metres' if j.type == 'prismatic' else 'turns q radians'}",
                    j.source,
                )
        if j.mimic is not None and j.mimic.joint not in {k.name for k in model.joints}:
            warn(f"joint '{j.name}' mimics unknown joint '{j.mimic.joint}'", j.source)

    parents: dict[str, list[str]] = {}
    for j in model.joints:
        parents.setdefault(j.child, []).append(j.name)
    for child, joint_names in parents.items():
        if len(joint_names) > 1:
            warn(
                f"link '{child}' is the child of {len(joint_names)} joints "
                f"({', '.join(joint_names)}): a URDF must be a tree; ROS tools pick one parent "
                "or, on a cycle, crash",
                model.link(child).source,
            )
    placed = model.forward_kinematics()
    unplaced = [link for link in model.links if link.name not in placed]
    if unplaced:
        warn(
            f"link{'s' if len(unplaced) > 1 else ''} "
            f"{', '.join(repr(link.name) for link in unplaced)} cannot be reached from the root "
            f"link {model.root_link.name!r}: their joints form a cycle apart from the tree "
            "(check_urdf accepts it; TF and simulators cannot place them)",
            unplaced[0].source,
        )
    names = {link.name for link in model.links} | {j.name for j in model.joints}
    for g in model.gazebo:
        if g.reference is not None and g.reference not in names:
            warn(
                f'<gazebo reference="{g.reference}"> names no link or joint of the robot',
                g.source,
            )
        for plugin in g.plugins:
            if plugin.filename in DIFF_DRIVE_PLUGINS:
                out.extend(_diff_drive(model, plugin))
    return out


def _inertia_problems(i: Inertial) -> list[str]:
    problems = []
    if i.mass <= 0:
        problems.append(f"mass {i.mass} is not positive")
    tensor = np.array([[i.ixx, i.ixy, i.ixz], [i.ixy, i.iyy, i.iyz], [i.ixz, i.iyz, i.izz]])
    # Scaled to 1 first: moments near the largest double would overflow inside the solver.
    scale = float(np.abs(tensor).max()) or 1.0
    with np.errstate(over="ignore"):  # a moment beyond the largest double prints as inf
        moments = np.linalg.eigvalsh(tensor / scale) * scale
    if moments.min() <= 0:
        problems.append(
            "inertia tensor is not positive definite (principal moments "
            + ", ".join(f"{m:.6g}" for m in moments)
            + ")"
        )
    else:
        a, b, c = sorted(moments)
        if a + b < c * (1 - 1e-9):
            problems.append(
                f"principal moments {a:.6g}, {b:.6g}, {c:.6g} break the triangle inequality "
                "(no real body has them)"
            )
    return problems


def _diff_drive(model: RobotModel, plugin: Any) -> list[Diagnostic]:
    left, right = plugin.param("leftJoint"), plugin.param("rightJoint")
    out: list[Diagnostic] = []
    joints = {j.name: j for j in model.joints}
    for role, name in (("leftJoint", left), ("rightJoint", right)):
        if name is not None and name not in joints:
            out.append(
                Diagnostic(
                    "warning",
                    f"diff-drive plugin '{plugin.name}': {role} '{name}' is not a joint",
                    plugin.source.best,
                )
            )
    if left not in joints or right not in joints:
        return out
    base = plugin.param("robotBaseFrame") or model.root_link.name
    frames = model.forward_kinematics()
    if base not in frames:
        base = model.root_link.name
    for role, name in (("leftJoint", left), ("rightJoint", right)):
        if joints[name].child not in frames:
            message = (
                f"diff-drive plugin '{plugin.name}': {role} '{name}' is not connected to the "
                f"root link '{base}', so it cannot drive the robot"
            )
            return [*out, Diagnostic("warning", message, plugin.source.best)]
    t_base_inv = np.linalg.inv(frames[base])
    y_left = float((t_base_inv @ frames[joints[left].child])[1, 3])
    y_right = float((t_base_inv @ frames[joints[right].child])[1, 3])
    if y_left < 0 < y_right or (y_left < y_right):
        legacy = (plugin.param("legacyMode") or "").strip().lower() in ("true", "1")
        compensation = (
            "legacyMode is true, which compensates as Gazebo 7 did (it swaps the wheels' roles "
            "back), so the robot still drives the right way"
            if legacy
            else "set legacyMode true (as Gazebo 7's default did) or swap leftJoint/rightJoint,"
            " or the robot turns the wrong way"
        )
        out.append(
            Diagnostic(
                "note" if legacy else "warning",
                f"diff-drive plugin '{plugin.name}': leftJoint '{left}' is on the right "
                f"(y = {y_left:+.3g} m in {base}) and rightJoint '{right}' on the left "
                f"(y = {y_right:+.3g} m); {compensation}",
                plugin.source.best,
            )
        )
    return out
