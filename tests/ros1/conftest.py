"""Fixtures of the ROS 1 face's tests."""

from __future__ import annotations

import pytest

from belvedere.msgs import TypeRegistry
from belvedere.ros1 import _show, _spec


@pytest.fixture
def pristine_types(monkeypatch: pytest.MonkeyPatch) -> TypeRegistry:
    """The type store as a fresh process has it, for the rosmsg/rossrv verbs: earlier tests
    in this process (bags, their fuzzers, a learner's packages) add types to the shared one,
    and a listing of every type would show theirs."""
    registry = TypeRegistry()
    monkeypatch.setattr(_show, "types", lambda: registry)
    monkeypatch.setattr(_spec, "types", lambda: registry)
    return registry
