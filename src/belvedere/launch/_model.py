"""What a launch file says, once read: parameters to set and nodes to start, each with the
file and line that said so."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, NamedTuple

from belvedere.errors import ParseError, SourceLocation

__all__ = ["LaunchConfig", "LaunchError", "LaunchFile", "LaunchNode", "LaunchParam"]


class LaunchError(ParseError):
    """A launch file that cannot be read or run."""


class LaunchFile(NamedTuple):
    """A file the launch reads while it is loaded: ``launch``, ``xacro`` (a robot description
    and what it includes), ``yaml`` (``<rosparam file>``, xacro's ``load_yaml``), ``urdf`` or
    ``text`` or ``binary`` (``<param textfile|binfile>``)."""

    kind: str
    path: str


@dataclass(frozen=True)
class LaunchParam:
    name: str
    """Resolved (``/ns/node/param``)."""
    value: Any
    source: SourceLocation | None = field(default=None, compare=False)


@dataclass(frozen=True)
class LaunchNode:
    """One ``<node>`` (or ``<test>``) to start."""

    pkg: str
    type: str
    name: str
    namespace: str = "/"
    args: str = ""
    output: str = "log"
    respawn: bool = False
    respawn_delay: float = 0.0
    required: bool = False
    cwd: str | None = None
    launch_prefix: str | None = None
    remappings: tuple[tuple[str, str], ...] = ()
    env: tuple[tuple[str, str], ...] = ()
    source: SourceLocation | None = field(default=None, compare=False)
    test_name: str | None = None
    """A ``<test>``'s ``test-name`` (None for a ``<node>``)."""
    time_limit: float = 60.0
    """A ``<test>``'s ``time-limit``: wall-clock seconds it may run (rostest's default 60)."""
    retry: int = 0
    """A ``<test>``'s ``retry``: how many more times a failing test runs."""

    @property
    def full_name(self) -> str:
        ns = self.namespace.rstrip("/")
        return f"{ns}/{self.name}"


@dataclass
class LaunchConfig:
    """Everything a launch file (and what it includes) asks for, in document order."""

    params: dict[str, LaunchParam] = field(default_factory=dict)
    nodes: list[LaunchNode] = field(default_factory=list)
    tests: list[LaunchNode] = field(default_factory=list)
    """``<test>`` nodes: listed and looked up as roslaunch does; ``belvedere test`` runs
    them."""
    files: list[LaunchFile] = field(default_factory=list)
    """What loading read, in order (the nodes read more once they start: ``launch --files``
    lists those too)."""
    deletions: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    dumps: list[tuple[str, str]] = field(default_factory=list)
    """(file, namespace) of each ``<rosparam command="dump">``, written once all is set."""
    clear: list[str] = field(default_factory=list)
    """Namespaces whose parameters are cleared before setting (``clear_params``)."""

    def node(self, name: str) -> LaunchNode | None:
        """The node (or test) of this full name (``/ns/name``; a relative name is global)."""
        wanted = name if name.startswith("/") else "/" + name
        return next((n for n in [*self.nodes, *self.tests] if n.full_name == wanted), None)

    def set_param(self, name: str, value: Any, source: SourceLocation | None) -> None:
        """Set one parameter (a dictionary value stays one value, as ``type="yaml"`` sets it;
        the loader unrolls ``<rosparam>`` mappings itself)."""
        self.params[name] = LaunchParam(name, value, source)
