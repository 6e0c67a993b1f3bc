"""``--foxglove [PORT]``: the Foxglove bridge beside a verb's graph (display, sim, launch);
:func:`belvedere.runtime.start_bridge` starts it."""

from __future__ import annotations

import argparse

from belvedere.cli._args import origin
from belvedere.runtime import BridgeOptions

__all__ = [
    "DEFAULT_PORT",
    "add_foxglove_options",
    "add_origin_option",
    "bridge_options",
    "port",
]

DEFAULT_PORT = 8765
"""belvedere.foxglove.DEFAULT_PORT, without importing the bridge to build the parser."""


def port(text: str) -> int:
    """A TCP port, 0 (any free one) to 65535."""
    try:
        value = int(text)
    except ValueError:
        value = -1
    if not 0 <= value <= 65535:
        msg = f"a port is a number from 0 to 65535 (0: any free port), not {text!r}"
        raise argparse.ArgumentTypeError(msg)
    return value


ORIGINS_HELP = (
    "also accept Foxglove clients from web pages of ORIGIN (scheme://host[:port]; repeatable; "
    "* for any): by default pages of this machine and Foxglove's web app "
    "(https://app.foxglove.dev) may connect, and clients that are no web page"
)
HOST_HELP = (
    "address the Foxglove bridge listens on (default: this machine only; another address "
    "needs the token in the printed URL)"
)


def add_foxglove_options(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--foxglove",
        nargs="?",
        const=DEFAULT_PORT,
        type=port,
        metavar="PORT",
        help=f"also serve the graph's topics to Foxglove on PORT (default: {DEFAULT_PORT})",
    )
    p.add_argument("--foxglove-host", default="127.0.0.1", metavar="HOST", help=HOST_HELP)
    add_origin_option(p, "--foxglove-allow-origin")


def add_origin_option(p: argparse.ArgumentParser, flag: str) -> None:
    """The bridge's ``--allow-origin`` (named ``flag``)."""
    p.add_argument(
        flag,
        action="append",
        default=[],
        type=origin,
        dest="foxglove_origins",
        metavar="ORIGIN",
        help=ORIGINS_HELP,
    )


def bridge_options(args: argparse.Namespace) -> BridgeOptions | None:
    """The bridge ``--foxglove`` asks for (None without it)."""
    wanted: int | None = getattr(args, "foxglove", None)
    if wanted is None:
        return None
    return BridgeOptions(
        port=wanted,
        host=args.foxglove_host,
        allow_origins=tuple(getattr(args, "foxglove_origins", ())),
    )
