"""The command line's options as a session's (``launch`` and ``run``): the boundary where
parsed arguments become the plain values :mod:`belvedere.runtime` takes."""

from __future__ import annotations

import argparse

from belvedere.cli._foxglove import bridge_options
from belvedere.cli._tool import graph_address
from belvedere.runtime import SessionOptions, ViewerOptions

__all__ = ["session_options"]


def session_options(args: argparse.Namespace) -> SessionOptions:
    """What ``--seed``, ``--duration``, ``--rtf``, ``--headless``, the viewer's, the
    bridge's, the scripted run's (``--pub``, ``--echo``) and the graph's options say."""
    return SessionOptions(
        address=graph_address(args),
        seed=args.seed,
        duration=args.duration,
        rtf=args.rtf,
        headless=args.headless,
        viewer=ViewerOptions(
            host=args.host, port=args.port, allow_origins=tuple(args.allow_origins)
        ),
        bridge=bridge_options(args),
        pubs=tuple(args.pub),
        echoes=tuple(args.echo),
    )
