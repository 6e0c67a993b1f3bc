"""Scripted runs, shared by ``belvedere sim`` and ``belvedere launch``: ``--rtf``,
``--duration``, ``--pub 'TOPIC TYPE YAML'`` and ``--echo TOPIC``.

With ``--rtf max --duration N`` a run is deterministic and as fast as the CPU allows; ``--pub``
messages are latched at start, ``--echo`` prints messages as ``belvedere topic echo`` does.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from typing import Any

from belvedere.errors import BelvedereError
from belvedere.graph import Graph, did_you_mean, resolve_name
from belvedere.msgs import message_from_args, message_to_yaml, types

__all__ = ["ScriptOptions", "add_script_options", "install_script", "parse_rtf"]


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


@dataclass(frozen=True)
class ScriptOptions:
    pubs: tuple[tuple[str, str, Any], ...]
    echoes: tuple[str, ...]

    @classmethod
    def from_args(cls, args: argparse.Namespace) -> ScriptOptions:
        """Check every ``--pub`` (bad YAML fails here, before anything starts)."""
        if args.duration is not None and not args.duration > 0:
            msg = f"--duration expects a positive number of seconds, got {args.duration!r}"
            raise BelvedereError(msg)
        pubs = []
        for spec in args.pub:
            words = spec.split(None, 2)
            if len(words) < 2:
                msg = f"--pub expects 'TOPIC TYPE YAML', got {spec!r}"
                raise BelvedereError(
                    msg, hint="e.g. --pub '/cmd_vel geometry_msgs/Twist {linear: {x: 0.2}}'"
                )
            try:
                topic, type_name = resolve_name(words[0]), types().resolve(words[1])
                msg_obj = message_from_args(type_name, words[2:])
            except BelvedereError as err:
                msg = f"--pub {spec!r}: {err.message}"
                raise BelvedereError(msg, hint=err.hint) from None
            pubs.append((topic, type_name, msg_obj))
        return cls(tuple(pubs), tuple(resolve_name(t) for t in args.echo))


def install_script(graph: Graph, options: ScriptOptions, *, name: str = "belvedere_script") -> None:
    """Add the ``--pub`` publishers and ``--echo`` printers to ``graph`` as a node of their own,
    ``name`` (none when there are neither).

    Echo subscriptions are made first, so they see the start-up messages too; a topic nobody
    publishes gets its type from the first ``--pub`` of it or is waited for."""
    if not options.pubs and not options.echoes:
        return
    node = graph.create_node(name)
    published_types = {topic: type_name for topic, type_name, _ in options.pubs}
    for topic in options.echoes:
        existing = graph.topics.get(topic)
        type_name = existing.type if existing else published_types.get(topic)
        if type_name is None:
            msg = f"--echo {topic}: no node in this run publishes or subscribes to it"
            known = {n for n, t in graph.topics.items() if t.publishers or t.subscriptions}
            hint = did_you_mean(topic, known | set(published_types))
            raise BelvedereError(
                msg, hint=hint or "check the topic name (see 'belvedere topic list')"
            )
        label = topic if len(options.echoes) > 1 else None
        node.subscribe(topic, type_name, _printer(label), queue_size=0)
    for topic, type_name, msg_obj in options.pubs:
        pub = node.publisher(topic, type_name, latch=True)
        pub.publish(msg_obj)


def _printer(label: str | None) -> Any:
    """Prints as ``topic echo``; with several topics each message starts ``# TOPIC``."""
    prefix = f"# {label}\n" if label else ""

    def show(msg: Any) -> None:
        sys.stdout.write(prefix + message_to_yaml(msg) + "\n---\n")

    return show
