"""What ``roslaunch --dump-params``, ``--nodes`` and ``--args NODE`` print, line for line, and
``--files``, which names every file the launch reads with its kind."""

from __future__ import annotations

import os
import shlex
import stat
from collections.abc import Mapping
from pathlib import Path

import yaml

from belvedere import nodes
from belvedere.launch._model import LaunchConfig, LaunchFile, LaunchNode

__all__ = [
    "DEFAULT_MASTER_URI",
    "dump_params",
    "file_list",
    "find_executable",
    "node_command",
    "node_list",
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
