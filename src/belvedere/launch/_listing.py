"""What ``roslaunch --dump-params``, ``--nodes`` and ``--args NODE`` print, and the summary it
shows before starting, line for line; and ``--files``, which names every file the launch reads
with its kind."""

from __future__ import annotations

import os
import shlex
import stat
from collections.abc import Mapping
from pathlib import Path

import yaml

from belvedere import nodes
from belvedere.launch._model import LaunchConfig, LaunchFile, LaunchNode
from belvedere.launch._names import global_ns

__all__ = [
    "DEFAULT_MASTER_URI",
    "dump_params",
    "file_list",
    "find_executable",
    "node_command",
    "node_list",
    "process_name",
    "summary",
]

DEFAULT_MASTER_URI = "http://localhost:11311/"
"""What ROS tools assume when ``ROS_MASTER_URI`` is not set."""


def dump_params(config: LaunchConfig) -> str:
    """Every parameter as one flat ``/full/name: value`` YAML mapping, sorted (a ``type="yaml"``
    mapping stays one value), and the blank line roslaunch ends it with."""
    flat = {name: param.value for name, param in config.params.items()}
    return yaml.safe_dump(flat) + "\n"


def file_list(config: LaunchConfig) -> str:
    """Every file the launch reads, once each, as ``KIND  PATH`` lines: what loading read
    (launch files, robot descriptions, parameter files), then what the nodes will read as
    their arguments say (rviz configs, worlds, maps)."""
    found = list(config.files)
    for spec in config.nodes:
        found.extend(LaunchFile(kind, path) for kind, path in nodes.files(spec))
    unique = dict.fromkeys(LaunchFile(f.kind, os.path.normpath(f.path)) for f in found)
    width = max((len(f.kind) for f in unique), default=0)
    return "".join(f"{f.kind:<{width}}  {f.path}\n" for f in unique)


def node_list(config: LaunchConfig) -> str:
    """The nodes' full names, then the tests', one a line."""
    return "\n".join(n.full_name for n in [*config.nodes, *config.tests]) + "\n"


SUMMARY_VALUE_CHARS = 20
"""roslaunch shows a parameter's value in its summary in at most this many characters."""


def _summary_value(value: object) -> str:
    """A value as roslaunch's summary shows it: Python's ``str``, cut to 20 characters
    (ending ``...``); ``<...>`` when what is shown holds a character that is not printable
    ASCII (trailing whitespace aside)."""
    text = str(value)
    if len(text) > SUMMARY_VALUE_CHARS:
        text = text[: SUMMARY_VALUE_CHARS - 3] + "..."
    if any(not 32 <= ord(c) <= 126 for c in text):
        trimmed = text.rstrip()
        if any(not 32 <= ord(c) <= 126 for c in trimmed):
            return "<...>"
        return trimmed
    return text


def summary(config: LaunchConfig) -> str:
    """roslaunch's summary of a launch: the namespaces it clears, every parameter (value
    shortened) and the nodes by namespace, each ``name (pkg/type)``; sorted as it sorts."""
    lines = ["", "SUMMARY", "========"]
    if config.clear:
        lines += ["", "CLEAR PARAMETERS"]
        lines += sorted(f" * {global_ns(ns)}" for ns in config.clear)
    if config.params:
        lines += ["", "PARAMETERS"]
        lines += sorted(f" * {p.name}: {_summary_value(p.value)}" for p in config.params.values())
    lines += ["", "NODES"]
    by_ns: dict[str, list[str]] = {}
    for node in config.nodes:
        ns = global_ns(node.namespace)
        by_ns.setdefault(ns, []).append(f"    {node.name} ({node.pkg}/{node.type})")
    for ns in sorted(by_ns):
        lines += [f"  {ns}", *sorted(by_ns[ns])]
    return "\n".join(lines) + "\n\n"


def process_name(node: LaunchNode, number: int) -> str:
    """roslaunch's name for the ``number``-th process it starts: ``ns/name-N``."""
    return f"{node.full_name.lstrip('/')}-{number}"


def find_executable(root: Path, name: str) -> Path | None:
    """The first executable file called ``name`` below a package's ``root``, walked as
    roslib walks it (symlinks followed, hidden directories skipped)."""
    for here, dirs, files in os.walk(root, followlinks=True):
        if name in files:
            path = Path(here) / name
            wanted = stat.S_IRUSR | stat.S_IXUSR
            if path.stat().st_mode & wanted == wanted:
                return path.absolute()
        dirs[:] = [d for d in dirs if not d.startswith(".")]
    return None


def node_command(
    node: LaunchNode, executable: str, *, environ: Mapping[str, str] | None = None
) -> str:
    """The line roslaunch starts ``node`` with: the environment it changes (``NAME="value"``:
    the master, ``ROS_NAMESPACE``, the ``<env>``s), the launch prefix, the executable, the
    args, the remappings and ``__name``."""
    base = dict(os.environ if environ is None else environ)
    env = dict(base)
    env["ROS_MASTER_URI"] = base.get("ROS_MASTER_URI") or DEFAULT_MASTER_URI
    env.pop("ROS_NAMESPACE", None)
    if node.namespace.rstrip("/"):
        env["ROS_NAMESPACE"] = node.namespace.rstrip("/")
    for key, value in node.env:
        env[key] = value
    words = [f'{k}="{v}"' for k, v in env.items() if base.get(k) != v]
    words += shlex.split(node.launch_prefix or "")
    words.append(executable)
    words += shlex.split(node.args)
    words += [f"{src}:={dst}" for src, dst in node.remappings]
    words.append(f"__name:={node.name}")
    return " ".join(words)
