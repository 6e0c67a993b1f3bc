"""rqt_reconfigure's page without a browser: the servers it finds, the widgets it makes from a
description, edits sent through ``set_parameters`` and the server's answers shown."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

from belvedere.graph import Graph
from belvedere.ros1.dynamic_reconfigure._description import (
    Description,
    Group,
    Param,
    enum_edit_method,
)
from belvedere.ros1.dynamic_reconfigure.graph_client import GraphClient, find_servers
from belvedere.ros1.dynamic_reconfigure.graph_server import GraphServer
from belvedere.viewer import ReconfigurePage
from tests.waiting import wait_until

SIZES = enum_edit_method(
    [
        {"name": "Small", "type": "int", "value": 0, "srcline": 1, "srcfile": "", "cconsttype": ""},
        {"name": "Large", "type": "int", "value": 2, "srcline": 2, "srcfile": "", "cconsttype": ""},
    ],
    "An enum to set size",
)


def _description() -> Description:
    """dynamic_tutorials' parameters, with a folder and a tab as a ``.cfg``'s groups make."""
    speeds = Group(
        "Speeds",
        "",
        id=1,
        parent=0,
        params=[Param.make("max_vel_x", "double", 0, "top speed", 0.5, 0.0, 1.0)],
    )
    extra = Group(
        "Extra", "tab", id=2, parent=0, params=[Param.make("note", "str", 0, "a note", "hi")]
    )
    root = Group(
        "Default",
        params=[
            Param.make("int_param", "int", 0, "An Integer parameter", 50, 0, 100),
            Param.make("bool_param", "bool", 0, "A Boolean parameter", True),
            Param.make("size", "int", 0, "A size", 0, 0, 2, SIZES),
            Param.make("gain", "double", 0, "unbounded", 1.0),
        ],
        groups=[speeds, extra],
    )
    return Description("Tutorials", root)


class Tutorial:
    """A server on ``/tutorial`` whose node keeps what its callback was given."""

    def __init__(self, graph: Graph) -> None:
        self.used: list[dict[str, Any]] = []
        node = graph.create_node("tutorial")
        described = _description()
        self.server = GraphServer(node, described, described.defaults, self._apply)

    def _apply(self, config: dict[str, Any], level: int) -> None:
        del level
        self.used.append(config)


@pytest.fixture
def graph() -> Iterator[Graph]:
    g = Graph(sim_time=False)
    g.start(rtf=None)
    yield g
    g.shutdown()


@pytest.fixture
def page(graph: Graph) -> Iterator[tuple[ReconfigurePage, Tutorial]]:
    tutorial = Tutorial(graph)
    p = ReconfigurePage(graph.create_node("rqt"), select=["tutorial"], poll=0.05)
    yield p, tutorial
    p.close()


def _panel(page: ReconfigurePage) -> Any:
    return wait_until(
        lambda: (p := page.panels.get("/tutorial")) is not None and len(p.widgets) == 6 and p,
        what="the tutorial server's six widgets",
    )


def test_finds_servers_by_service_and_by_description_topic(graph: Graph) -> None:
    Tutorial(graph)
    other = graph.create_node("other")
    other.publisher("/lonely/parameter_descriptions", "dynamic_reconfigure/ConfigDescription")
    probe = graph.create_node("probe")
    from belvedere.graph import GraphTopics

    topics = GraphTopics(graph)
    assert find_servers(probe, topics) == ["/lonely", "/tutorial"]
    topics.close()


def test_widgets_follow_the_description(page: tuple[ReconfigurePage, Tutorial]) -> None:
    p, _ = page
    panel = _panel(p)
    kinds = {name: [type(h).__name__ for h in w.handles] for name, w in panel.widgets.items()}
    assert kinds == {
        "int_param": ["GuiSliderHandle"],  # with its number field
        "bool_param": ["GuiCheckboxHandle"],
        "size": ["GuiDropdownHandle"],
        "gain": ["GuiNumberHandle"],  # no range: no slider
        "max_vel_x": ["GuiSliderHandle"],
        "note": ["GuiTextHandle"],
    }
    slider = panel.widgets["int_param"].handles[0]
    assert (slider.min, slider.max, slider.value) == (0, 100, 50)
    assert panel.widgets["size"].handles[0].options == ("Small (0)", "Large (2)")
    assert p.servers == ["/tutorial"]
    assert p._ticks["/tutorial"].value is True


def test_an_edit_reaches_the_node_and_the_clamped_answer_is_shown(
    page: tuple[ReconfigurePage, Tutorial],
) -> None:
    p, tutorial = page
    panel = _panel(p)
    panel.send("int_param", 500)
    assert tutorial.used[-1]["int_param"] == 100  # the server clamps to its range
    assert panel.widgets["int_param"].handles[0].value == 100
    assert "the server kept 100" in panel.status.content
    panel.send("size", 1)  # not one of the enum's values: refused, the old value shown again
    assert "refused" in panel.status.content
    assert panel.widgets["size"].handles[0].value == "Small (0)"


def test_a_change_by_another_client_shows_up(
    graph: Graph, page: tuple[ReconfigurePage, Tutorial]
) -> None:
    p, tutorial = page
    panel = _panel(p)
    other = GraphClient(graph.create_node("dynparam"), "/tutorial")
    other.set({"max_vel_x": 0.25, "bool_param": False, "note": "set elsewhere"})
    widgets = panel.widgets
    wait_until(
        lambda: (
            widgets["max_vel_x"].handles[0].value == 0.25
            and widgets["bool_param"].handles[0].value is False
            and widgets["note"].handles[0].value == "set elsewhere"
        ),
        what="the page to show the other client's values",
        detail=lambda: [h.value for w in widgets.values() for h in w.handles],
    )
    assert tutorial.used[-1]["max_vel_x"] == 0.25


def test_unticking_closes_the_server(page: tuple[ReconfigurePage, Tutorial]) -> None:
    p, _ = page
    _panel(p)
    p.select("/tutorial", shown=False)
    assert "/tutorial" not in p.panels
    assert p._ticks["/tutorial"].value is False
