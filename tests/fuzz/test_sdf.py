"""Fuzzing the SDF reader and the physics world build with mutated example worlds and
models: only belvedere's own errors may escape, and nothing hangs."""

from __future__ import annotations

from pathlib import Path

from hypothesis import given
from hypothesis import strategies as st

from belvedere.errors import BelvedereError
from belvedere.graph import Graph
from belvedere.packages import PackageIndex
from belvedere.sim.physics import PhysicsSimulation
from belvedere.world import ModelPaths, read_world
from tests.fuzz._mutate import Mutation, fuzz_settings, mutations, run_bounded, xml_mutant

SEEDS = (
    "mbot_gazebo/worlds/playground.world",
    "mbot_gazebo/worlds/box_room.world",
    "mbot_gazebo/worlds/empty.world",
    "mbot_gazebo/models/belvedere_table/model.sdf",
    "mbot_gazebo/models/belvedere_crate/model.sdf",
    "mbot_gazebo/models/belvedere_post/model.sdf",
)
TAGS = (
    *("model", "link", "joint", "include", "uri", "pose", "frame", "inertial", "mass"),
    *("collision", "visual", "geometry", "box", "mesh", "plane", "polyline", "state"),
)


@fuzz_settings(200)
@given(st.sampled_from(SEEDS), mutations())
def test_sdf_mutants(examples_copy: Path, seed: str, edits: list[Mutation]) -> None:
    original = examples_copy / seed
    text = xml_mutant(original.read_text(encoding="utf-8"), edits, TAGS)
    path = original.with_name("fuzz_" + original.name)
    path.write_text(text, encoding="utf-8")
    paths = ModelPaths.from_environment(packages=PackageIndex([examples_copy]), environ={})
    with run_bounded(60):
        try:
            world = read_world(path, model_paths=paths)
            PhysicsSimulation(Graph(), world)
        except BelvedereError:
            pass
