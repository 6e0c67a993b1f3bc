"""``belvedere param list|get|set|load|dump|delete`` — rosparam, against the running graph."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import yaml

from belvedere.bounded import YAML_TEXT_BYTES, read_regular_text
from belvedere.cli._tool import action_parsers, graph_address
from belvedere.errors import BelvedereError
from belvedere.fileio import write_file
from belvedere.graph import resolve_name
from belvedere.runtime import open_tool

__all__ = ["add_parser", "run"]


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser("param", parents=[common], help="read and write the parameter tree")
    verb = action_parsers(p, common)

    verb("list", "parameter names").add_argument("namespace", nargs="?", default="/")
    verb("get", "a value (a namespace gives a mapping)").add_argument("name")
    v = verb("set", "set a value (YAML)")
    v.add_argument("name")
    v.add_argument("value")
    v = verb("load", "load a YAML file into a namespace")
    v.add_argument("file")
    v.add_argument("namespace", nargs="?", default="/")
    v = verb("dump", "write parameters as YAML (to FILE or stdout)")
    v.add_argument("file", nargs="?")
    v.add_argument("namespace", nargs="?", default="/")
    verb("delete", "delete a parameter or namespace").add_argument("name")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    tool = open_tool(graph_address(args), "param")
    try:
        ask = tool.transport.param_request
        action = args.action
        if action == "list":
            for name in ask({"op": "list", "name": resolve_name(args.namespace)}):
                sys.stdout.write(name + "\n")
        elif action == "get":
            value = ask({"op": "get", "name": resolve_name(args.name)})
            text = yaml.safe_dump(value, default_flow_style=False).rstrip()
            sys.stdout.write(text.removesuffix("\n...") + "\n")
        elif action == "set":
            try:
                value = yaml.safe_load(args.value)
            except yaml.YAMLError as err:
                msg = f"value {args.value!r} is not valid YAML: {err}"
                raise BelvedereError(msg) from None
            ask({"op": "set", "name": resolve_name(args.name), "value": value})
        elif action == "load":
            path = Path(args.file)
            text = read_regular_text(path, limit=YAML_TEXT_BYTES, what="")
            ask(
                {
                    "op": "load",
                    "name": resolve_name(args.namespace),
                    "yaml": text,
                    "source": str(path),
                }
            )
        elif action == "dump":
            text = ask({"op": "dump", "name": resolve_name(args.namespace)})
            if args.file and args.file != "-":
                write_file(args.file, text)
            else:
                sys.stdout.write(text)
        elif action == "delete":
            ask({"op": "delete", "name": resolve_name(args.name)})
        return 0
    finally:
        tool.close()
