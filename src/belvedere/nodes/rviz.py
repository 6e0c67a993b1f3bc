"""rviz: the browser viewer, with the displays of an ``.rviz`` file (``-d FILE``)."""

from __future__ import annotations

import shlex
import sys

from belvedere.graph import Node
from belvedere.nodes._registry import FileClaim, NodeSpec, Session, Starter, end_node

__all__ = ["ANONYMOUS", "EXECUTABLES", "FILES", "JOINING", "PACKAGE"]

PACKAGE = "rviz"

_OPTIONS = (
    ("-h [ --help ]", "Produce this help message"),
    ("-s [ --splash-screen ] arg", "A custom splash-screen image to display"),
    ("--help-file arg", "A custom html file to show as the help screen"),
    ("-d [ --display-config ] arg", "A display config file (.rviz) to load"),
    ("--fullscreen", "Trigger fullscreen display"),
    ("-f [ --fixed-frame ] arg", "Set the fixed frame"),
    ("-l [ --ogre-log ]", "Enable the Ogre.log file (output in cwd) and console output."),
    ("--in-mc-wrapper", "Signal that this is running inside a master-chooser wrapper"),
    (
        "--opengl arg",
        "Force OpenGL version (use '--opengl 210' for OpenGL 2.1 compatibility mode)",
    ),
    ("--disable-anti-aliasing", "Prevent rviz from trying to use anti-aliasing when rendering."),
    ("--no-stereo", "Disable the use of stereo rendering."),
    ("-v [ --verbose ]", "Enable debug visualizations"),
    ("--log-level-debug", "Sets the ROS logger level to debug."),
)
"""rviz 1.14's command-line options, as its ``--help`` lists them (the browser viewer takes
``-d``; the rest are a desktop window's and are accepted without effect)."""
_WIDTH = 80
"""boost::program_options's line length (a description ends a column before it)."""


def usage() -> str:
    """rviz's ``--help`` text: the options in two columns, descriptions wrapped as boost does."""
    import textwrap

    column = max(len(name) for name, _ in _OPTIONS) + 3
    lines = ["rviz command line options:"]
    for name, text in _OPTIONS:
        wrapped = textwrap.wrap(text, _WIDTH - column - 1, break_on_hyphens=False)
        # boost keeps the space it broke a line at
        wrapped = [line + " " for line in wrapped[:-1]] + wrapped[-1:]
        lines.append(f"  {name}".ljust(column) + wrapped[0])
        lines.extend(" " * column + more for more in wrapped[1:])
    return "\n".join(lines) + "\n"


def _config(spec: NodeSpec) -> str | None:
    """The ``-d FILE`` (``--display-config FILE``) of rviz's arguments, if any."""
    words = shlex.split(spec.args)
    config = None
    for flag in ("-d", "--display-config"):
        if flag in words and words.index(flag) + 1 < len(words):
            config = words[words.index(flag) + 1]
    return config


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    if {"-h", "--help"} & set(shlex.split(spec.args)):
        sys.stdout.write(usage())
        # rviz ends with status 1 after its help (its init reports "not started")
        end_node(session, node, 1)
        return
    config = _config(spec)
    if config is not None:
        session.rviz_config = config
    session.want_viewer = True


def _files(spec: NodeSpec) -> list[tuple[str, str]]:
    config = _config(spec)
    return [] if config is None else [("rviz", config)]


EXECUTABLES: dict[str, Starter] = {"rviz": _start}
FILES: dict[str, FileClaim] = {"rviz": _files}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
ANONYMOUS = frozenset({"rviz"})
"""Named as roscpp's ``AnonymousName`` names it when run without ``__name:=``."""
