"""xacro's command line, as launch files and users spell it.

``$(find xacro)/xacro --inorder 'robot.xacro' arg:=1``, ``xacro.py robot.xacro`` and
``belvedere xacro robot.xacro`` all parse here, so they run the same code.
"""

from __future__ import annotations

import argparse
import os
import shlex
from dataclasses import dataclass, field

from belvedere.description.xacro._dialects import Dialect
from belvedere.description.xacro._errors import XacroError
from belvedere.mappings import split_mappings

__all__ = [
    "XacroCommand",
    "add_xacro_arguments",
    "command_from_namespace",
    "is_xacro_program",
    "parse_xacro_argv",
    "parse_xacro_command",
]

INORDER_NOTICE = (
    "xacro: in-order processing became default in ROS Melodic. You can drop the option."
)


@dataclass
class XacroCommand:
    """One xacro invocation."""

    input: str
    mappings: dict[str, str] = field(default_factory=dict)
    dialect: Dialect = Dialect.AUTO
    output: str | None = None
    deps: bool = False
    check_order: bool = False
    fix: bool = False
    root_dir: str | None = None
    python2_floats: bool = False
    strict: bool = False
    notices: list[str] = field(default_factory=list)


def add_xacro_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("input", metavar="FILE", help="the xacro file")
    p.add_argument("-o", dest="output", metavar="OUT", help="write to OUT instead of stdout")
    p.add_argument(
        "--dialect",
        choices=[d.value for d in Dialect],
        default=None,
        help="auto (default): modern, expanding legacy unprefixed tags with a warning; "
        "modern: exactly xacro 2.1.1; melodic: ROS Melodic in-order; kinetic: two-pass",
    )
    p.add_argument("--deps", action="store_true", help="print the files it reads and exit")
    p.add_argument("--inorder", "-i", action="store_true", help="in-order processing (the default)")
    p.add_argument(
        "--legacy",
        "--oldorder",
        dest="legacy",
        action="store_true",
        help="two-pass processing of ROS Kinetic (same as --dialect kinetic)",
    )
    p.add_argument(
        "--check-order",
        action="store_true",
        help="report whether the file gives the same result in-order and two-pass",
    )
    p.add_argument(
        "--fix",
        action="store_true",
        help="rewrite legacy files (and the files they include) to prefixed xacro tags, "
        "in place, keeping FILE.orig backups",
    )
    p.add_argument("--root-dir", metavar="DIR", help="resolve relative paths against DIR")
    p.add_argument(
        "--python2-floats",
        action="store_true",
        help="print floats as ROS 1 did under Python 2: 12 significant digits (0.3, not "
        "0.30000000000000004)",
    )
    p.add_argument(
        "--strict",
        action="store_true",
        help="refuse to read files outside the model's package roots (default: warn)",
    )
    p.add_argument("--xacro-ns", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("--includes", action="store_true", help=argparse.SUPPRESS)


def command_from_namespace(ns: argparse.Namespace, mappings: dict[str, str]) -> XacroCommand:
    notices: list[str] = []
    if ns.inorder:
        notices.append(INORDER_NOTICE)
    if ns.legacy:
        dialect = Dialect.KINETIC
    elif ns.dialect:
        dialect = Dialect(ns.dialect)
    else:
        dialect = Dialect.AUTO
    return XacroCommand(
        input=ns.input,
        mappings=mappings,
        dialect=dialect,
        output=ns.output,
        deps=ns.deps,
        check_order=ns.check_order,
        fix=ns.fix,
        root_dir=ns.root_dir,
        python2_floats=ns.python2_floats,
        strict=ns.strict,
        notices=notices,
    )


XACRO_PROGRAMS = ("xacro", "xacro.py")


def is_xacro_program(word: str) -> bool:
    """Whether a command's first word runs xacro (``xacro``, ``xacro.py``, ``…/xacro/xacro``)."""
    return os.path.basename(word) in XACRO_PROGRAMS


def parse_xacro_command(command: str) -> XacroCommand:
    """Parse a whole xacro command as a launch file's ``<param command=…>`` holds it, after
    its ``$(…)`` substitutions: ``/path/to/xacro --inorder 'robot.xacro' name:=value``."""
    words = shlex.split(command)
    if not words or not is_xacro_program(words[0]):
        msg = f"not a xacro command: {command!r} (expected xacro or xacro.py first)"
        raise XacroError(msg)
    return parse_xacro_argv(words[1:])


def parse_xacro_argv(argv: list[str]) -> XacroCommand:
    """Parse a xacro command line as written in a launch file (without the program name)."""
    rest, mappings = split_mappings(argv)
    parser = argparse.ArgumentParser(prog="xacro", add_help=False, exit_on_error=False)
    add_xacro_arguments(parser)
    parser.add_argument("-q", action="store_true")
    parser.add_argument("-v", action="count")
    parser.add_argument("--verbosity", type=int)
    try:
        ns = parser.parse_args(rest)
    except (argparse.ArgumentError, SystemExit) as err:
        msg = f"bad xacro command line {' '.join(argv)!r}: {err}"
        raise XacroError(msg) from None
    return command_from_namespace(ns, mappings)
