"""``belvedere param list|get|set|load|dump|delete`` — rosparam, against the running graph.

The output is Debian rosparam's, line for line (:mod:`belvedere.graph`'s ``param_*_text``
functions write it). ``-v`` after the action is rosparam's verbose (what it did, on
stdout); before the verb, and as ``--verbose`` anywhere, it is belvedere's (more logging).
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

import yaml

from belvedere.bounded import YAML_TEXT_BYTES, read_regular, read_regular_text
from belvedere.cli._tool import add_graph_options, graph_address
from belvedere.errors import BelvedereError
from belvedere.fileio import write_file
from belvedere.graph import (
    param_documents,
    param_dump_text,
    param_get_text,
    param_leaf_lines,
    param_leaves,
    param_shown,
    resolve_name,
)
from belvedere.runtime import open_tool
from belvedere.yamlfile import Loader

__all__ = ["add_parser", "run"]

BINARY_BYTES = 16 << 20
"""The largest file ``set -b`` stores (a parameter travels whole in one request)."""


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser("param", parents=[common], help="read and write the parameter tree")
    actions = p.add_subparsers(dest="action", metavar="ACTION", required=True)

    def verb(name: str, help_text: str, *, verbose: bool = True) -> argparse.ArgumentParser:
        # "resolve": this -v replaces the common one (which stays as --verbose)
        v = actions.add_parser(name, parents=[common], help=help_text, conflict_handler="resolve")
        add_graph_options(v)
        if verbose:
            v.add_argument(
                "-v",
                dest="said",
                action="store_true",
                help="turn on verbose output (rosparam's -v: what it does, on stdout)",
            )
        return v

    verb("list", "parameter names", verbose=False).add_argument("namespace", nargs="?")
    v = verb("get", "a value (a namespace gives a mapping)")
    v.add_argument("-p", dest="pretty", action="store_true", help="pretty print (not YAML-safe)")
    v.add_argument("name")
    v = verb("set", "set a value (YAML; a mapping sets each of its leaves)")
    files = v.add_mutually_exclusive_group()
    files.add_argument("-t", "--textfile", metavar="TEXT_FILE", help="the text of a file")
    files.add_argument("-b", "--binfile", metavar="BINARY_FILE", help="the bytes of a file")
    v.add_argument("name")
    v.add_argument("value", nargs="?")
    v = verb("load", "load a YAML file (- for stdin) into a namespace")
    v.add_argument("file")
    v.add_argument("namespace", nargs="?")
    v = verb("dump", "write parameters as YAML (to FILE, or stdout)")
    v.add_argument("file", nargs="?")
    v.add_argument("namespace", nargs="?")
    verb("delete", "delete a parameter or namespace").add_argument("name")
    p.set_defaults(run=run)


def _say(*lines: str) -> None:
    for line in lines:
        sys.stdout.write(line + "\n")


def _value(args: argparse.Namespace) -> Any:
    """What ``set`` sets: a text file's text, a binary file's bytes, or the YAML value."""
    if args.textfile:
        return read_regular_text(args.textfile, limit=YAML_TEXT_BYTES, what="text file")
    if args.binfile:
        return read_regular(args.binfile, limit=BINARY_BYTES, what="binary file")
    if args.value is None:
        msg = "param set: give a value, or a file with -t/--textfile or -b/--binfile"
        raise BelvedereError(msg)
    # rosparam reads an empty argument as the empty string (its #2237), not YAML's null
    text = args.value if args.value != "" else "!!str"
    try:
        return yaml.load(text, Loader=Loader)
    except yaml.YAMLError as err:
        msg = f"value {args.value!r} is not valid YAML: {err}"
        raise BelvedereError(msg) from None


def _load_text(file: str) -> str:
    if file == "-":
        return sys.stdin.read()
    return read_regular_text(file, limit=YAML_TEXT_BYTES, what="parameter file")


def run(args: argparse.Namespace) -> int:
    said = getattr(args, "said", False)
    tool = open_tool(graph_address(args), "param")
    try:
        ask = tool.transport.param_request
        action = args.action
        if action == "list":
            # rosparam lists the names under NS/ (a parameter's own name is not among them)
            prefix = resolve_name(args.namespace or "/").rstrip("/") + "/"
            names = sorted(n for n in ask({"op": "list", "name": "/"}) if n.startswith(prefix))
            _say("\n".join(names))
        elif action == "get":
            name = resolve_name(args.name)
            if said:
                _say(f"getting parameter [{name}]")
            sys.stdout.write(param_get_text(ask({"op": "get", "name": name}), pretty=args.pretty))
        elif action == "set":
            name, value = resolve_name(args.name), _value(args)
            set_leaves = param_leaves(name, value)  # refuses what the server cannot hold
            ask({"op": "update", "name": name, "value": value})
            if said:
                _say(*(f"set parameter [{n}] to [{param_shown(v)}]" for n, v in set_leaves))
        elif action == "load":
            _load(args, ask, said=said)
        elif action == "dump":
            if said:
                _say(f"dumping namespace [{args.namespace or ''}] to file [{args.file}]")
            name = resolve_name(args.namespace or "/")
            tree = ask({"op": "get", "name": name})
            if said:
                _say(*param_leaf_lines(tree, name))
            if args.file and args.file != "-":
                write_file(args.file, param_dump_text(tree))
            else:
                sys.stdout.write(param_dump_text(tree))
        elif action == "delete":
            name = resolve_name(args.name)
            if name == "/":
                # the root always has a value: ROS empties it instead
                ask({"op": "set", "name": "/", "value": {}})
                if said:
                    _say("deleted ENTIRE parameter server")
            else:
                ask({"op": "delete", "name": name})
                if said:
                    _say(f"deleted parameter [{name}]")
        return 0
    finally:
        tool.close()


def _load(args: argparse.Namespace, ask: Any, *, said: bool) -> None:
    stdin = args.file == "-"
    if said:
        _say("reading parameters from stdin" if stdin else f"reading parameters from [{args.file}]")
    text = _load_text(args.file)
    source = "<stdin>" if stdin else args.file
    docs = param_documents(text, resolve_name(args.namespace or "/"), source=source)
    for _, ns, named in docs:
        if said and named:
            _say(f"reading parameters into namespace [{ns}]")
    for doc, ns, _ in docs:
        param_leaves(ns, doc)  # the whole file is checked before any of it is set
    for doc, ns, _ in docs:
        if said:
            _say(*param_leaf_lines(doc, ns))
        ask({"op": "update", "name": ns, "value": doc})
