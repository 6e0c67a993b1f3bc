"""Fuzzing the ``.rviz`` reader: mutated configs give belvedere's own error or a config that
survives a write and a second read unchanged; nothing else escapes, nothing hangs."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml
from hypothesis import given
from hypothesis import strategies as st

from belvedere.errors import BelvedereError
from belvedere.viewer import read_rviz, write_rviz
from tests.conftest import EXAMPLES
from tests.fuzz._mutate import (
    HOSTILE_TEXT,
    Mutation,
    fuzz_settings,
    mutations,
    run_bounded,
    text_mutant,
)
from tests.viewer.test_rviz import EVERY_CLASS, ROS2

SEEDS = {
    "every": EVERY_CLASS,
    "ros2": ROS2,
    "nav": (EXAMPLES / "mbot_navigation" / "rviz" / "nav.rviz").read_text(encoding="utf-8"),
}
TOKENS = (*HOSTILE_TEXT, ": ", "- ", "{", "}", "[", "]", "~", "Value: ", "Class: rviz/Group")

yaml_values: st.SearchStrategy[Any] = st.recursive(
    st.none()
    | st.booleans()
    | st.integers()
    | st.floats(allow_nan=False)
    | st.text(max_size=12)
    | st.sampled_from(("255; 0; 0", "rviz/Group", "rviz/Map", "costmap", "/scan", "Value")),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=8), inner),
    max_leaves=6,
)


def _slots(node: Any, out: list[tuple[Any, Any]]) -> list[tuple[Any, Any]]:
    """Every (container, key) in a parsed document, parents before children."""
    items = node.items() if isinstance(node, dict) else enumerate(node)
    for key, value in list(items):
        out.append((node, key))
        if isinstance(value, dict | list):
            _slots(value, out)
    return out


def _round_trip(path: Path) -> None:
    try:
        config = read_rviz(path)
    except BelvedereError:
        return
    out = path.with_name("written.rviz")
    write_rviz(config, out)
    assert read_rviz(out) == config


@fuzz_settings(150)
@given(
    st.sampled_from(sorted(SEEDS)),
    st.lists(st.tuples(st.integers(0, 10_000), yaml_values | st.just(...)), min_size=1, max_size=4),
)
def test_rviz_value_mutants(
    tmp_path_factory: pytest.TempPathFactory, seed: str, edits: list[tuple[int, Any]]
) -> None:
    doc = yaml.safe_load(SEEDS[seed])
    for index, value in edits:
        slots = _slots(doc, [])
        if not slots:
            break
        container, key = slots[index % len(slots)]
        if value is ... and isinstance(container, dict):
            del container[key]
        elif value is not ...:
            container[key] = value
    path = tmp_path_factory.mktemp("rviz") / "mutant.rviz"
    path.write_text(yaml.safe_dump(doc, allow_unicode=True), encoding="utf-8")
    with run_bounded(30):
        _round_trip(path)


@fuzz_settings(150)
@given(st.sampled_from(sorted(SEEDS)), mutations())
def test_rviz_text_mutants(
    tmp_path_factory: pytest.TempPathFactory, seed: str, edits: list[Mutation]
) -> None:
    path = tmp_path_factory.mktemp("rviz") / "mutant.rviz"
    path.write_text(text_mutant(SEEDS[seed], edits, TOKENS), encoding="utf-8")
    with run_bounded(30):
        _round_trip(path)
