"""Fuzzing xacro with mutated example xacros: structure (tags, attributes, includes, macro
calls) rather than expressions. Only belvedere's own errors may escape, and nothing hangs."""

from __future__ import annotations

from pathlib import Path

from hypothesis import given
from hypothesis import strategies as st

from belvedere.description.urdf import RobotModel, load_robot
from belvedere.errors import BelvedereError
from belvedere.packages import PackageIndex
from tests.fuzz._mutate import Mutation, fuzz_settings, mutations, run_bounded, xml_mutant

SEEDS = (
    "mbot_description/urdf/xacro/gazebo/mbot_with_kinect_gazebo.xacro",
    "mbot_description/urdf/xacro/gazebo/mbot_base_gazebo.xacro",
    "mbot_description/urdf/xacro/gazebo/mbot_gazebo_modern.xacro",
    "mbot_description/urdf/xacro/sensors/lidar_gazebo.xacro",
    "rbx1_description/urdf/turtlebot.urdf.xacro",
    "marm_description/urdf/marm.xacro",
)
TAGS = tuple(
    f"{prefix}{keyword}"
    for prefix in ("xacro:", "")
    for keyword in (
        "include",
        "macro",
        "property",
        "if",
        "unless",
        "insert_block",
        "call",
        "element",
        "attribute",
        "arg",
    )
)


@fuzz_settings(200)
@given(st.sampled_from(SEEDS), mutations())
def test_xacro_mutants(examples_copy: Path, seed: str, edits: list[Mutation]) -> None:
    original = examples_copy / seed
    text = xml_mutant(original.read_text(encoding="utf-8"), edits, TAGS)
    path = original.with_name("fuzz_" + original.name)
    path.write_text(text, encoding="utf-8")
    with run_bounded(60):
        try:
            parsed = load_robot(path, packages=PackageIndex([examples_copy]))
            if not parsed.fatal:
                RobotModel.from_parsed(parsed).to_urdf()
        except BelvedereError:
            pass
