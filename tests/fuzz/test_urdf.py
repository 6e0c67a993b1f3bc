"""Fuzzing the URDF reader, the check lint and the physics build with mutated example robots:
only belvedere's own errors may escape, and nothing hangs."""

from __future__ import annotations

import contextlib
from functools import cache
from pathlib import Path

from hypothesis import given
from hypothesis import strategies as st

from belvedere.description.checks import check_file
from belvedere.description.urdf import RobotModel
from belvedere.description.xacro import process_file
from belvedere.errors import BelvedereError
from belvedere.graph import Graph
from belvedere.packages import PackageIndex
from belvedere.sim.physics import PhysicsSimulation
from tests.conftest import EXAMPLES
from tests.fuzz._mutate import Mutation, fuzz_settings, mutations, run_bounded, xml_mutant

XACROS = (
    "mbot_description/urdf/xacro/gazebo/mbot_with_laser_gazebo.xacro",
    "rbx1_description/urdf/turtlebot.urdf.xacro",
    "marm_description/urdf/marm.xacro",
)
TAGS = (
    *("link", "joint", "inertial", "inertia", "origin", "mass", "geometry", "box", "mesh"),
    *("cylinder", "sphere", "visual", "collision", "material", "gazebo", "plugin", "limit"),
)


@cache
def seeds() -> tuple[str, ...]:
    """The example URDF and what the example xacros expand to."""
    packages = PackageIndex([EXAMPLES])
    urdf = (EXAMPLES / "mbot_description/urdf/urdf/mbot_base.urdf").read_text()
    return (urdf, *(process_file(EXAMPLES / x, packages=packages) for x in XACROS))


@fuzz_settings(200)
@given(st.integers(0, 3), mutations())
def test_urdf_mutants(examples_copy: Path, seed: int, edits: list[Mutation]) -> None:
    text = xml_mutant(seeds()[seed], edits, TAGS)
    path = examples_copy / "mbot_description/urdf/urdf/fuzz.urdf"
    path.write_text(text, encoding="utf-8")
    packages = PackageIndex([examples_copy])
    with run_bounded(60):
        report = check_file(path, packages=packages, simulated=True)
        if report.model is None:
            return
        model = report.model
        RobotModel.from_string(model.to_urdf(), path="round-trip.urdf")
        model.forward_kinematics()
        with contextlib.suppress(BelvedereError):
            PhysicsSimulation(Graph()).spawn(model, packages=packages)
