"""rqt_plot: numeric fields plotted in a browser page (``rqt_plot /odom/pose/pose/position/x``).

Its arguments as rqt_plot takes them: field paths separated by spaces or commas
(``/turtle1/pose/x:y`` for two fields of one topic), ``-P``/``--pause`` to start paused,
``-e``/``--empty`` to start with none. The page's port is the ``~port`` parameter (8090).
"""

from __future__ import annotations

from belvedere.graph import Node
from belvedere.nodes._registry import NodeSpec, Session, Starter, StartError, stopping_on_bad_values
from belvedere.nodes._rqt import open_page, words

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE"]

PACKAGE = "rqt_plot"
PORT = 8090


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    from belvedere.errors import BelvedereError
    from belvedere.viewer import PlotPage

    args = words(spec)
    flags = {w for w in args if w.startswith("-")}
    unknown = flags - {"-P", "--pause", "-e", "--empty"}
    if unknown:
        msg = f"{spec.full_name}: rqt_plot has no option {sorted(unknown)[0]} (-P, -e, paths)"
        raise StartError(msg, spec.source)
    paths = [] if flags & {"-e", "--empty"} else [w for w in args if w not in flags]
    page = open_page(spec, node, PORT)
    try:
        plot = PlotPage(node, paths, page)
    except BelvedereError as err:
        page.close()
        msg = f"{spec.full_name}: {err.message}"
        raise StartError(msg, spec.source) from None
    plot.paused.value = bool(flags & {"-P", "--pause"})
    session.closers.append(plot.close)


EXECUTABLES: dict[str, Starter] = {"rqt_plot": stopping_on_bad_values(_start)}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
