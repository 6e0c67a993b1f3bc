"""Fuzzing the launch file reader with mutated example launch files: only belvedere's own
errors may escape, and nothing hangs. (Programs named by a mutated ``<param command>`` are
not found: the test runs with an empty PATH.)"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from belvedere.errors import BelvedereError
from belvedere.launch import load_launch
from belvedere.packages import PackageIndex
from tests.conftest import EXAMPLES
from tests.fuzz._mutate import Mutation, fuzz_settings, mutations, run_bounded, xml_mutant

SEEDS = tuple(sorted(str(p.relative_to(EXAMPLES)) for p in EXAMPLES.glob("*/launch/*.launch")))
TAGS = ("arg", "param", "rosparam", "node", "include", "group", "remap", "env", "machine")


@pytest.fixture(scope="module")
def no_programs(tmp_path_factory: pytest.TempPathFactory) -> Iterator[None]:
    empty = tmp_path_factory.mktemp("no-programs")
    saved = os.environ.get("PATH")
    os.environ["PATH"] = str(empty)
    yield
    if saved is None:
        del os.environ["PATH"]
    else:
        os.environ["PATH"] = saved


@fuzz_settings(200)
@given(st.sampled_from(SEEDS), mutations())
def test_launch_mutants(
    examples_copy: Path, no_programs: None, seed: str, edits: list[Mutation]
) -> None:
    original = examples_copy / seed
    text = xml_mutant(original.read_text(encoding="utf-8"), edits, TAGS)
    path = original.with_name("fuzz_" + original.name)
    path.write_text(text, encoding="utf-8")
    with run_bounded(60), contextlib.suppress(BelvedereError):
        load_launch(path, packages=PackageIndex([examples_copy]))
