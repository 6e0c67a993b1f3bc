"""``belvedere service list|call|type|info|find|args|uri`` — rosservice, against the running
graph. ``uri`` and ``info``'s ``URI:`` are the Zenoh key a service answers on (rosservice
prints the node's ``rosrpc://`` address)."""

from __future__ import annotations

import argparse
import sys

from belvedere.cli._tool import action_parsers, graph_address
from belvedere.msgs import canonical, message_from_args, message_to_yaml, short
from belvedere.ros1 import known_type, service_args
from belvedere.runtime import offered_service, open_tool

__all__ = ["add_parser", "run"]


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser("service", parents=[common], help="list and call services")
    verb = action_parsers(p, common)
    verb("list", "offered services")
    verb("type", "a service's type").add_argument("service")
    verb("info", "a service's node, key, type and arguments").add_argument("service")
    verb("args", "the fields of a service's request").add_argument("service")
    verb("uri", "the Zenoh key a service answers on").add_argument("service")
    verb("find", "the services of a type").add_argument("type")
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
        if args.action == "find":
            wanted = canonical(known_type("srv", args.type), "srv")
            found = [
                n
                for n, offered in info.services.items()
                if any(typ == wanted for typ, _ in offered)
            ]
            sys.stdout.write("\n".join(sorted(found)) + "\n")  # none: an empty line
            return 0
        name, srv_type, offered = offered_service(info, args.service)
        uri = tool.transport.service_key(name)
        if args.action == "type":
            out = [short(srv_type)]
        elif args.action == "args":
            out = [" ".join(service_args(srv_type))]
        elif args.action == "uri":
            out = [uri]
        elif args.action == "info":
            out = [f"Node: {node}" for _, node in sorted(offered)]
            out += [f"URI: {uri}", f"Type: {short(srv_type)}"]
            out.append(f"Args: {' '.join(service_args(srv_type))}")
        else:
            tool.graph.start(rtf=None)
            request = message_from_args(f"{srv_type}_Request", args.values)
            response = tool.node.call_service(name, srv_type, request, timeout=args.timeout)
            out = [message_to_yaml(response)]
        sys.stdout.write("".join(line + "\n" for line in out))
        return 0
    finally:
        tool.close()
