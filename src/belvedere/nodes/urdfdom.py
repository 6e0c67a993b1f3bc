"""urdfdom (liburdfdom-tools): ``urdf_to_graphiz FILE [OUTPUT]`` — the robot's link/joint
tree written to ``ROBOT.gv`` and ``ROBOT.pdf`` in the working directory (or ``OUTPUT.gv`` and
``OUTPUT.pdf``), as urdfdom's tool names them; a xacro file is expanded first."""

from __future__ import annotations

import shlex
import sys

from belvedere.description.graphiz import urdf_to_graphiz
from belvedere.description.urdf import RobotModel
from belvedere.graph import Node
from belvedere.nodes._registry import FileClaim, NodeSpec, Session, Starter, StartError, end_node
from belvedere.pictures import write_pictures

__all__ = ["EXECUTABLES", "FILES", "JOINING", "PACKAGE"]

PACKAGE = "urdfdom"
USAGE = "urdf_to_graphiz input.xml [OUTPUT]"


def _words(spec: NodeSpec) -> list[str]:
    words = shlex.split(spec.args)
    if not 1 <= len(words) <= 2:
        msg = f"usage: {USAGE} (writes ROBOT.gv and ROBOT.pdf, or OUTPUT.gv and OUTPUT.pdf)"
        raise StartError(msg, spec.source)
    return words


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    words = _words(spec)
    model = RobotModel.from_path(words[0])
    written = write_pictures(urdf_to_graphiz(model), words[1] if len(words) > 1 else model.name)
    for path in written:
        sys.stdout.write(f"Created file {path.name}\n")
    sys.stdout.flush()
    end_node(session, node)


def _files(spec: NodeSpec) -> list[tuple[str, str]]:
    return [("urdf", _words(spec)[0])]


EXECUTABLES: dict[str, Starter] = {"urdf_to_graphiz": _start, "urdf_to_graphviz": _start}
FILES: dict[str, FileClaim] = dict.fromkeys(EXECUTABLES, _files)
JOINING = frozenset(EXECUTABLES)
"""A tool: it runs beside the graph that runs, as a ROS executable would."""
