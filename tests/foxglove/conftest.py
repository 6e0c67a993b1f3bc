"""A graph in simulated time and a bridge serving it on any free port."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from belvedere.foxglove import FoxgloveBridge
from belvedere.graph import Graph


@pytest.fixture
def graph() -> Iterator[Graph]:
    g = Graph(sim_time=True)
    yield g
    g.shutdown()


@pytest.fixture
def bridge(graph: Graph) -> Iterator[FoxgloveBridge]:
    b = FoxgloveBridge(graph, port=0)
    yield b
    b.close()
