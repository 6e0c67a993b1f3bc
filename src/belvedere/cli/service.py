"""``belvedere service list|call|type`` — rosservice, against the running graph."""

from __future__ import annotations

import argparse
import sys

from belvedere.cli._tool import action_parsers, graph_address
from belvedere.errors import BelvedereError
from belvedere.graph import did_you_mean, resolve_name
from belvedere.msgs import message_from_args, message_to_yaml, short
from belvedere.runtime import open_tool

__all__ = ["add_parser", "run"]


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser("service", parents=[common], help="list and call services")
    verb = action_parsers(p, common)
    verb("list", "offered services")
    verb("type", "a service's type").add_argument("service")
    v = verb("call", "call a service")
    v.add_argument("service")
    v.add_argument("values", nargs="*", help="request as YAML (one mapping or per field)")
    v.add_argument("--timeout", type=float, default=5.0)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    tool = open_tool(graph_address(args), "service")
    try:
        info = tool.info()
        if args.action == "list":
            for name in sorted(info.services):
                sys.stdout.write(name + "\n")
            return 0
        name = resolve_name(args.service)
        offered = sorted(info.services.get(name, ()))
        if not offered:
            msg = f"service {name} is not offered by any node"
            hint = did_you_mean(name, info.services) or "see 'belvedere service list'"
            raise BelvedereError(msg, hint=hint)
        srv_type = offered[0][0]
        if args.action == "type":
            sys.stdout.write(short(srv_type) + "\n")
            return 0
        tool.graph.start(rtf=None)
        request = message_from_args(f"{srv_type}_Request", args.values)
        response = tool.node.call_service(name, srv_type, request, timeout=args.timeout)
        sys.stdout.write(message_to_yaml(response) + "\n")
        return 0
    finally:
        tool.close()
