"""Scripted runs, shared by ``belvedere sim`` and ``belvedere launch``: ``--rtf``,
``--duration``, ``--pub 'TOPIC TYPE YAML'`` and ``--echo TOPIC``.

With ``--rtf max --duration N`` a run is deterministic and as fast as the CPU allows; ``--pub``
messages are latched at start, ``--echo`` prints messages as ``belvedere topic echo`` does
(:mod:`belvedere.runtime` installs them on the graph).
"""

from __future__ import annotations

import argparse

from belvedere.runtime import ScriptOptions

__all__ = ["add_script_options", "parse_rtf", "script_options"]


def parse_rtf(text: str) -> float | None:
    """``max`` → None (as fast as possible); a positive number → that real-time factor."""
    if text.strip().lower() == "max":
        return None
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not value > 0 or value == float("inf"):
        msg = f"--rtf expects a positive number or 'max', got {text!r}"
        raise argparse.ArgumentTypeError(msg)
    return value


def add_script_options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--rtf",
        type=parse_rtf,
        default=1.0,
        metavar="1|max|N",
        help="real-time factor: 1 (default), N times faster, or max (as fast as possible)",
    )
    p.add_argument(
        "--duration", type=float, metavar="SECONDS", help="stop after SECONDS of simulated time"
    )
    p.add_argument(
        "--pub",
        action="append",
        default=[],
        metavar="'TOPIC TYPE YAML'",
        help="publish a message once at start, latched (repeatable)",
    )
    p.add_argument(
        "--echo",
        action="append",
        default=[],
        metavar="TOPIC",
        help="print the messages of TOPIC to stdout, as YAML documents ending '---' "
        "(repeatable: each then starts '# TOPIC'); stdout is then the echo's alone: nodes' "
        'log lines and scripts\' output (output="screen") go to stderr',
    )


def script_options(args: argparse.Namespace) -> ScriptOptions:
    """``--pub``, ``--echo`` and ``--duration``, checked (bad YAML fails here, before anything
    starts)."""
    return ScriptOptions.parse(args.pub, args.echo, duration=args.duration)
