"""What the graph tools share: ``--domain`` and ``--endpoint`` (which graph to join), and
``belvedere VERB ACTION`` sub-parsers; :mod:`belvedere.runtime` joins."""

from __future__ import annotations

import argparse
import os
import time
from collections.abc import Callable

from belvedere.cli._report import notice
from belvedere.errors import BelvedereError
from belvedere.graph import (
    MAX_DOMAIN,
    TransportError,
    check_domain,
    check_token,
    endpoint_host,
    new_token,
)
from belvedere.runtime import GraphAddress

__all__ = [
    "action_parsers",
    "add_graph_options",
    "add_host_options",
    "graph_address",
    "serve_for",
]


def _domain(text: str) -> int:
    try:
        return check_domain(text)
    except TransportError as err:
        raise argparse.ArgumentTypeError(err.message) from None


def add_graph_options(
    p: argparse.ArgumentParser, *, hosts: bool = True, ros_master: bool = True
) -> None:
    """``--domain`` and ``--endpoint``: which graph to join; with ``hosts``, the options of a
    graph across hosts too (:func:`add_host_options`; a verb whose own ``--listen`` came
    first leaves them to the environment, ``BELVEDERE_CONNECT`` …); with ``ros_master``,
    ``--ros-master``: a ROS 1 master it joins too."""
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
    if hosts:
        add_host_options(p)


def _endpoint(text: str) -> str:
    try:
        endpoint_host(text)
    except BelvedereError as err:
        raise argparse.ArgumentTypeError(err.message) from None
    return text


def _token(text: str) -> str:
    try:
        return check_token(text, where="--token")
    except BelvedereError as err:
        raise argparse.ArgumentTypeError(err.message) from None


def add_host_options(p: argparse.ArgumentParser) -> None:
    """``--listen``, ``--connect``, ``--token``, ``--discover``: one graph across hosts."""
    # marks the verbs that have them: roswtf's own --listen SECONDS is no endpoint
    p.set_defaults(host_options=True)
    p.add_argument(
        "--listen",
        type=_endpoint,
        metavar="tls/IP:PORT",
        help="open this graph to other hosts on IP:PORT (BELVEDERE_LISTEN), guarded by a "
        "token printed at start (or BELVEDERE_TOKEN); tls/ encrypts, tcp/ does not",
    )
    p.add_argument(
        "--connect",
        type=_endpoint,
        metavar="tls/HOST:PORT",
        help="join the graph another host opened with --listen (BELVEDERE_CONNECT); "
        "needs its token",
    )
    p.add_argument(
        "--token",
        type=_token,
        metavar="TOKEN",
        help="the graph's token (BELVEDERE_TOKEN; the environment keeps it out of 'ps')",
    )
    p.add_argument(
        "--discover",
        action="store_true",
        help="find the graph's peers by Zenoh multicast scouting on the LAN "
        "(BELVEDERE_DISCOVER; needs the token)",
    )


def _apply_host_options(args: argparse.Namespace) -> None:
    """Put ``--listen``/``--connect``/``--token``/``--discover`` in the environment, where
    the transport and every process this one starts (a launch's nodes) read them; a
    ``--listen`` without a token makes one and prints how other hosts join."""
    if not getattr(args, "host_options", False):
        return
    env = os.environ
    for option, var in (("listen", "BELVEDERE_LISTEN"), ("connect", "BELVEDERE_CONNECT")):
        value = getattr(args, option, None)
        if value is not None:
            env[var] = value
    if getattr(args, "token", None):
        env["BELVEDERE_TOKEN"] = args.token
    if getattr(args, "discover", False):
        env["BELVEDERE_DISCOVER"] = "1"
    listen = getattr(args, "listen", None)
    if listen is not None and not env.get("BELVEDERE_TOKEN"):
        env["BELVEDERE_TOKEN"] = new_token()
        notice(
            f"graph: open to other hosts on {listen}, guarded by a token; on another host:\n"
            f"  export BELVEDERE_CONNECT={listen} BELVEDERE_TOKEN={env['BELVEDERE_TOKEN']}"
        )


def graph_address(args: argparse.Namespace) -> GraphAddress:
    """The graph that ``--domain``/``--endpoint`` name (a verb without them: the default);
    the host options (:func:`add_host_options`) take effect here."""
    _apply_host_options(args)
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
