"""rqt_reconfigure: every dynamic_reconfigure server of the graph, and their parameters, on a
page in the browser (:class:`belvedere.viewer.ReconfigurePage`) instead of a Qt window.

``rqt_reconfigure [NODE …]`` opens the servers named at once, as ROS's does. The page is
served on 127.0.0.1, on the port of the private parameter ``~port`` (0, the default: a free
one); its URL is printed. Like rqt's, the node is named anonymously (``rqt_gui_py_node_…``).
"""

from __future__ import annotations

import shlex
import sys

from belvedere.graph import Node
from belvedere.nodes._registry import (
    NodeSpec,
    Session,
    Starter,
    StartError,
    end_node,
    port_param,
    stopping_on_bad_values,
)

__all__ = ["ANONYMOUS", "EXECUTABLES", "JOINING", "NAMES", "PACKAGE"]

PACKAGE = "rqt_reconfigure"

USAGE = """usage: rqt_reconfigure [-h] [NODE ...]

The parameters of the graph's dynamic_reconfigure servers, in the browser.

positional arguments:
  NODE        a server to open at once (e.g. /move_base)

options:
  -h, --help  show this help message and exit
  _port:=N    serve the page on port N (default: a free port)
"""


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    from belvedere.viewer import ReconfigurePage, ViewerError

    words = shlex.split(spec.args)
    if "-h" in words or "--help" in words:
        sys.stdout.write(USAGE)
        end_node(session, node)
        return
    unknown = [w for w in words if w.startswith("-")]
    if unknown:
        msg = f"{spec.full_name}: rqt_reconfigure takes no option {', '.join(unknown)}"
        raise StartError(msg, spec.source, hint="rqt_reconfigure [NODE ...]; see --help")
    port = port_param(node, 0)
    try:
        page = ReconfigurePage(node, port=port, select=words)
    except (ViewerError, OSError) as err:
        msg = f"{spec.full_name}: cannot serve the page: {err}"
        raise StartError(msg, spec.source) from None
    session.closers.append(page.close)
    served = page.server.get_port()
    if port and served != port:  # viser moves on to the next free port
        sys.stderr.write(f"rqt_reconfigure: port {port} is taken; serving on {served}\n")
    sys.stderr.write(f"rqt_reconfigure: {page.url}\n")


EXECUTABLES: dict[str, Starter] = {"rqt_reconfigure": stopping_on_bad_values(_start)}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
ANONYMOUS = frozenset(EXECUTABLES)
"""rqt names its node ``rqt_gui_py_node_<pid>`` when nothing renames it."""
NAMES = {"rqt_reconfigure": "rqt_gui_py_node"}
