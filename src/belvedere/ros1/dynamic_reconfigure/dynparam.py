"""``dynparam``: get, set, list, dump and load a reconfigurable node's configuration, as
``rosrun dynamic_reconfigure dynparam`` does (its commands, arguments and output).

It runs as a rospy script (``belvedere run dynamic_reconfigure dynparam …``). ``dump`` writes
plain YAML mappings; ROS's writes its ``Config`` class as a ``!!python/object/new`` tag, which
``load`` reads as the mapping it holds (ROS reads it with YAML's unsafe loader; nothing here
constructs an object a file names).
"""

from __future__ import annotations

import optparse
import sys
from collections.abc import Callable, Sequence
from typing import Any

import yaml

from belvedere.ros1.dynamic_reconfigure._exceptions import DynamicReconfigureParameterException
from belvedere.ros1.dynamic_reconfigure.client import Client
from belvedere.ros1.rospy import (
    ROSException,
    ROSInterruptException,
    ServiceException,
    _state,
    get_param,
    init_node,
    myargv,
)

__all__ = ["main", "reconfigurable_nodes"]


def _say(text: object, stream: Any = None) -> None:
    """Print as ROS's tool prints (a line on stdout, or on ``stream``)."""
    (stream or sys.stdout).write(f"{text}\n")


_USAGE = """dynparam is a command-line tool for getting, setting, and
deleting parameters of a dynamically configurable node.

Commands:
\tdynparam set                  configure node
\tdynparam set_from_parameters  copy configuration from parameter server
\tdynparam get                  get node configuration
\tdynparam load                 load configuration from file
\tdynparam dump                 dump configuration to file
\tdynparam list                 list configurable nodes

Type dynparam <command> -h for more detailed usage, e.g. 'dynparam get -h'
"""
_SUFFIX = "/set_parameters"


def reconfigurable_nodes() -> list[str]:
    """The nodes on the graph that serve ``set_parameters``, sorted."""
    runtime = _state.required()
    names = set(runtime.graph.services)
    if runtime.transport is not None:
        names |= set(runtime.transport.info(timeout=1.0).services)
    return sorted(n[: -len(_SUFFIX)] for n in names if n.endswith(_SUFFIX))


def _parser(usage: str) -> optparse.OptionParser:
    parser = optparse.OptionParser(usage=usage, prog="dynparam")
    parser.add_option(
        "-t", "--timeout", action="store", type="float", default=None, help="timeout in secs"
    )
    return parser


def _node_and(args: list[str], parser: optparse.OptionParser, what: str | None) -> list[str]:
    if not args:
        parser.error("invalid arguments. Please specify a node name")
    if what is not None and len(args) == 1:
        parser.error(f"invalid arguments. Please specify {what}")
    if len(args) > (1 if what is None else 2):
        parser.error("too many arguments")
    return args


def _connect() -> None:
    init_node("dynparam", anonymous=True)


_CONFIG_TAG = "tag:yaml.org,2002:python/object/new:dynamic_reconfigure.encoding.Config"


class _Loader(yaml.SafeLoader):
    """YAML's safe loader, reading ROS's dumped ``Config`` objects as their mappings."""


def _config_object(loader: yaml.SafeLoader, node: yaml.Node) -> Any:
    if not isinstance(node, yaml.MappingNode):
        return loader.construct_object(node)
    fields = loader.construct_mapping(node, deep=True)
    items = fields.get("dictitems", {})
    return dict(items) if isinstance(items, dict) else {}


_Loader.add_constructor(_CONFIG_TAG, _config_object)


def _set_params(node: str, params: dict[str, Any], timeout: float | None) -> None:
    client = Client(node, timeout=timeout)
    try:
        client.update_configuration(params)
    except DynamicReconfigureParameterException as err:
        _say(f"error updating parameters: {err}")


def _get(node: str, timeout: float | None) -> Any:
    return Client(node, timeout=timeout).get_configuration(timeout=timeout)


def _plain(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


def do_list(argv: list[str]) -> None:
    _connect()
    for node in reconfigurable_nodes():
        _say(node)


def do_get(argv: list[str]) -> None:
    parser = _parser("Usage: %prog get [options] node")
    options, args = parser.parse_args(argv)
    (node,) = _node_and(args, parser, None)
    _connect()
    params = _get(node, options.timeout)
    if params is not None:
        _say(params)


def do_set(argv: list[str]) -> None:
    usage = (
        "Usage: %prog set [options] node parameter value\n"
        "   or: %prog set [options] node values\n\nExamples:\n"
        "  dynparam set wge100_camera camera_url foo\n"
        "  dynparam set wge100_camera \"{'camera_url':'foo', 'brightness':58}\" "
    )
    args = [s for s in argv if not s.startswith("-") or s[1:2].isdigit()]
    flags = [s for s in argv if s not in args]
    parser = _parser(usage)
    options, _ = parser.parse_args(flags)
    if len(args) > 3:
        parser.error("too many arguments")
    if len(args) < 2:
        parser.error(
            "invalid arguments. Please specify either a node name, parameter name and "
            "parameter value, or a node name and a YAML dictionary"
        )
    if len(args) == 2:
        values = yaml.safe_load(args[1])
        if not isinstance(values, dict):
            parser.error(
                "invalid arguments. Please specify either a node name, parameter name and "
                "parameter value, or a node name and a YAML dictionary"
            )
    else:
        values = {args[1]: args[2]}
    _connect()
    try:
        _set_params(args[0], values, options.timeout)
    except (ServiceException, ROSException):
        _say(f"couldn't set parameters at node {args[0]}")


def do_set_from_parameters(argv: list[str]) -> None:
    parser = _parser("Usage: %prog set_from_parameters [options] node")
    options, args = parser.parse_args(argv)
    (node,) = _node_and(args, parser, None)
    _connect()
    params = get_param("~", None)
    if not isinstance(params, dict) or not params:
        _say("error updating parameters: no parameters found on parameter server", sys.stderr)
        return
    _set_params(node, params, options.timeout)


def do_load(argv: list[str]) -> None:
    parser = _parser("Usage: %prog load [options] node file")
    options, args = parser.parse_args(argv)
    node, path = _node_and(args, parser, "an input file")
    params: dict[str, Any] = {}
    try:
        with open(path, encoding="utf-8") as f:
            for doc in yaml.load_all(f, Loader=_Loader):
                if isinstance(doc, dict):
                    params.update(doc)
    except (OSError, yaml.YAMLError) as err:
        _say(f"error: cannot load {path}: {err}", sys.stderr)
        sys.exit(1)
    params.pop("groups", None)
    _connect()
    _set_params(node, params, options.timeout)


def do_dump(argv: list[str]) -> None:
    parser = _parser("Usage: %prog dump [options] node file")
    options, args = parser.parse_args(argv)
    node, path = _node_and(args, parser, "an output file")
    _connect()
    params = _get(node, options.timeout)
    if params is not None:
        with open(path, "w", encoding="utf-8") as f:
            yaml.safe_dump(_plain(params), f)
        return
    _say(f"couldn't get parameters from node {node}")


_COMMANDS: dict[str, Callable[[list[str]], None]] = {
    "list": do_list,
    "set_from_parameters": do_set_from_parameters,
    "set": do_set,
    "get": do_get,
    "load": do_load,
    "dump": do_dump,
}


def main(argv: Sequence[str] | None = None) -> None:
    """dynparam's command line (``argv``: rospy's ``myargv()`` by default)."""
    args = list(myargv() if argv is None else argv)
    command = _COMMANDS.get(args[1]) if len(args) > 1 else None
    if command is None:
        _say(_USAGE)
        sys.exit(1)
    try:
        command(args[2:])
    except ROSInterruptException:
        pass
    except ROSException as err:  # no server within --timeout: one line, not a traceback
        _say(f"error: {err}", sys.stderr)
        sys.exit(1)
    return
