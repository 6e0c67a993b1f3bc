"""rqt_console's rows and filters, on the Log messages a node really publishes."""

from __future__ import annotations

from belvedere.graph import SEVERITIES, Graph, LogFilter, LogRow, log_row


def test_a_nodes_warning_becomes_a_row_with_its_location() -> None:
    graph = Graph()
    node = graph.create_node("talker")
    logged: list[LogRow] = []
    console = graph.create_node("console")
    console.subscribe("/rosout", "rosgraph_msgs/Log", lambda m: logged.append(log_row(m)))
    node.logger.warning("battery at %d%%", 15)
    graph.spin_once()
    row = logged[0]
    assert (row.severity, row.node, row.message) == ("WARN", "/talker", "battery at 15%")
    assert row.location.startswith(__file__ + ":test_a_nodes_warning_becomes_a_row")
    assert row.location.rsplit(":", 1)[1].isdigit()


def test_filters_pick_severities_node_and_text_and_highlight() -> None:
    rows = [
        LogRow(2, "/a", 1, "hello world", "f:g:1", ()),
        LogRow(4, "/b/driver", 2, "Battery low", "f:g:2", ()),
        LogRow(8, "/b/driver", 3, "motor stalled", "f:g:3", ()),
    ]
    assert next(r.stamp for r in rows) == "0.000000001"
    assert [r.message for r in rows if LogFilter().shows(r)] == [r.message for r in rows]
    warn_up = LogFilter(levels={4, 8, 16})
    assert [r.node for r in rows if warn_up.shows(r)] == ["/b/driver", "/b/driver"]
    by_text = LogFilter(node="DRIVER", text="battery")
    assert [r.message for r in rows if by_text.shows(r)] == ["Battery low"]
    marked = LogFilter(highlight="stall")
    assert [r.level for r in rows if marked.highlights(r)] == [8]
    assert list(SEVERITIES.values()) == ["DEBUG", "INFO", "WARN", "ERROR", "FATAL"]
