"""The ROS executables belvedere has, one module per ROS package, for ``launch`` and ``run``.

Each module names its package (``PACKAGE``) and its executables by their ROS names
(``EXECUTABLES``: name → starter; ``JOINING``: those that join a graph already running
when ``run`` starts them; ``TRANSFORMS``: the fixed transforms an executable publishes;
``FILES``: the files it reads, as its arguments name them); a
starter gets the running :class:`Session`, the node's :class:`NodeSpec` (what ``<node>`` or
``rosrun`` said) and its graph node. Adding a package is adding one module to
:data:`MODULES`.
"""

from __future__ import annotations

from belvedere.nodes._registry import (
    MODULES,
    NodeSpec,
    Session,
    Starter,
    StartError,
    anonymous,
    end_node,
    end_when,
    executables,
    files,
    find,
    joins_running_graph,
    node_name,
    package_names,
    transforms,
)

__all__ = [
    "MODULES",
    "NodeSpec",
    "Session",
    "StartError",
    "Starter",
    "anonymous",
    "end_node",
    "end_when",
    "executables",
    "files",
    "find",
    "joins_running_graph",
    "node_name",
    "package_names",
    "transforms",
]
