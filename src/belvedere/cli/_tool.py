"""What the graph tools share: ``--domain`` and ``--endpoint`` (which graph to join), and
``belvedere VERB ACTION`` sub-parsers; :mod:`belvedere.runtime` joins."""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

from belvedere.graph import MAX_DOMAIN, TransportError, check_domain
from belvedere.runtime import GraphAddress

__all__ = ["action_parsers", "add_graph_options", "graph_address", "serve_for"]


def _domain(text: str) -> int:
    try:
        return check_domain(text)
    except TransportError as err:
        raise argparse.ArgumentTypeError(err.message) from None


def add_graph_options(p: argparse.ArgumentParser, *, ros_master: bool = True) -> None:
    """``--domain`` and ``--endpoint``: which graph to join; ``--ros-master``: a ROS 1
    master it joins too."""
    p.add_argument(
        "--domain",
        type=_domain,
        metavar="N",
        help=f"the graph to join, 0 to {MAX_DOMAIN} (default: BELVEDERE_DOMAIN or 0); "
        "domain N meets on tcp/127.0.0.1:<7450+N>",
    )
    p.add_argument(
        "--endpoint",
        metavar="ENDPOINT",
        help="Zenoh endpoint of the graph (default: BELVEDERE_ENDPOINT, else the domain's)",
    )
    if ros_master:
        p.add_argument(
            "--ros-master",
            metavar="URI",
            help="also join this running ROS 1 master (http://HOST:11311, a robot's or "
            "roscore's): the graph's nodes register there as a ROS 1 node",
        )


def graph_address(args: argparse.Namespace) -> GraphAddress:
    """The graph that ``--domain``/``--endpoint`` name (a verb without them: the default)."""
    return GraphAddress(
        endpoint=getattr(args, "endpoint", None),
        domain=getattr(args, "domain", None),
        ros_master=getattr(args, "ros_master", None),
    )


def action_parsers(
    parser: argparse.ArgumentParser, common: argparse.ArgumentParser
) -> Callable[[str, str], argparse.ArgumentParser]:
    """A maker of ``belvedere VERB ACTION`` sub-parsers, each with the common options,
    ``--domain`` and ``--endpoint``."""
    actions = parser.add_subparsers(dest="action", metavar="ACTION", required=True)

    def action(name: str, help_text: str) -> argparse.ArgumentParser:
        sub = actions.add_parser(name, parents=[common], help=help_text)
        add_graph_options(sub)
        return sub

    return action


def serve_for(duration: float | None) -> None:
    """Wait ``duration`` wall-clock seconds (None: for ever) while the graph's threads serve;
    Ctrl-C ends the wait as the user's way to stop, not as an error."""
    try:
        deadline = None if duration is None else time.monotonic() + duration
        while deadline is None or time.monotonic() < deadline:
            time.sleep(0.2)
    except KeyboardInterrupt:
        pass
