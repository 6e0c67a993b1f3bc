"""Where :func:`find` looks: the package modules, imported only when asked for."""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any, Final, Protocol

from belvedere.errors import BelvedereError, ParseError, SourceLocation
from belvedere.graph import Graph, Node
from belvedere.packages import PackageIndex

if TYPE_CHECKING:
    from belvedere.tf import JointStatePublisher

__all__ = [
    "MODULES",
    "FileClaim",
    "NodeSpec",
    "ParamLookup",
    "Session",
    "StartError",
    "Starter",
    "TransformClaim",
    "anonymous",
    "end_node",
    "end_when",
    "executables",
    "files",
    "find",
    "frame_claim",
    "joins_running_graph",
    "node_name",
    "package_names",
    "port_param",
    "stopping_on_bad_values",
    "transforms",
]


class StartError(ParseError):
    """A node that cannot start as its ``<node>`` (or command line) asks, at that line."""


class NodeSpec(Protocol):
    """What starting one node needs to know (a launch file's ``<node>``, a ``rosrun``)."""

    @property
    def pkg(self) -> str: ...
    @property
    def type(self) -> str: ...
    @property
    def name(self) -> str: ...
    @property
    def namespace(self) -> str: ...
    @property
    def args(self) -> str: ...
    @property
    def source(self) -> SourceLocation | None: ...
    @property
    def full_name(self) -> str: ...


class Session(Protocol):
    """What a running launch (or ``run``) offers its nodes: the graph and packages, the one
    physics simulation, the viewer's wishes, and actions for after every node exists."""

    graph: Graph
    packages: PackageIndex
    sim: Any
    sim_controls: Any
    """The viewer's Simulation folder when the simulation is not a physics one (ArbotiX's
    fake drivers: :class:`belvedere.sim.kinematic.DriverControls`)."""
    joint_publisher: JointStatePublisher | None
    gui_joints: bool
    rviz_config: str | None
    want_viewer: bool
    canvases: list[Any]
    """2D simulations for the viewer to draw (:class:`belvedere.viewer.Canvas`)."""
    deferred: list[Callable[[], None]]
    """Run after every node exists (spawn_model)."""
    controllers: list[Callable[[], None]]
    """Run after that (controller spawners)."""
    spawned: dict[str, Any]
    """Model name → the node spec that spawned it."""
    finished: dict[str, int]
    """Nodes that ended by themselves (:func:`end_node`): full name → exit status."""
    closers: list[Callable[[], None]]
    """Run when the session ends (a recorder closes its bag), last added first."""

    def param_source(self, name: str) -> SourceLocation | None:
        """Where the parameter ``name`` (a full name) was set: its YAML line for one a
        ``<rosparam>`` loaded, the ``<param>``'s line, None if unknown."""
        ...


Starter = Callable[[Session, NodeSpec, Node], None]


def stopping_on_bad_values(start: Callable[[Session, NodeSpec, Node], object]) -> Starter:
    """A starter that runs ``start`` and turns its ``ValueError`` (a bad parameter, naming
    it) into the node's one error at its launch line, as every parameter-reading node does."""

    def starter(session: Session, spec: NodeSpec, node: Node) -> None:
        try:
            start(session, spec, node)
        except ValueError as err:
            message = f"{spec.full_name}: {err}"
            raise StartError(message, spec.source) from None

    return starter


def port_param(node: Node, default: int) -> int:
    """The node's ``~port`` parameter (``default`` when unset).

    Raises:
        ValueError: it is no port number (naming the parameter, for
            :func:`stopping_on_bad_values`).
    """
    port = node.get_param("~port", default)
    if isinstance(port, bool) or not isinstance(port, int) or not 0 <= port <= 65535:
        msg = f"parameter ~port: expected a port number (0 to 65535), got {port!r}"
        raise ValueError(msg)
    return port


ParamLookup = Callable[[str, Any], Any]
"""A node's private parameter (name without ``~``) with a default."""
FileClaim = Callable[[NodeSpec], list[tuple[str, str]]]
"""The files a node will read, as its arguments say: (kind, path) pairs (a module's ``FILES``:
executable → claim; ``launch --files`` lists them)."""
TransformClaim = Callable[[NodeSpec, ParamLookup], list[tuple[str, str]]]
"""The transforms (parent, child frame) a node will publish, as its arguments and parameters
say (a module's ``TRANSFORMS``: executable → claim)."""


def frame_claim(
    defaults: Mapping[str, Any], parent: str, child: str, *, when: str | None = None
) -> TransformClaim:
    """The claim of one transform whose frames are the parameters ``parent`` and ``child``;
    none while the flag parameter ``when`` is false. ``defaults`` are the node's."""

    def claim(spec: NodeSpec, param: ParamLookup) -> list[tuple[str, str]]:
        del spec
        if when is not None and not param(when, defaults[when]):
            return []
        return [(str(param(parent, defaults[parent])), str(param(child, defaults[child])))]

    return claim


MODULES: Final = {
    "amcl": "amcl",
    "arbotix_python": "arbotix_python",
    "controller_manager": "controller_manager",
    "depthimage_to_laserscan": "depthimage_to_laserscan",
    "fake_localization": "fake_localization",
    "foxglove_bridge": "foxglove_bridge",
    "gazebo_ros": "gazebo_ros",
    "gmapping": "gmapping",
    "hector_mapping": "hector_mapping",
    "image_publisher": "image_publisher",
    "joint_state_publisher": "joint_state_publisher",
    "joy": "joy",
    "joint_state_publisher_gui": "joint_state_publisher_gui",
    "map_server": "map_server",
    "move_base": "move_base",
    "robot_state_publisher": "robot_state_publisher",
    "rosbag": "rosbag",
    "rostest": "rostest",
    "rqt_console": "rqt_console",
    "rqt_graph": "rqt_graph",
    "rqt_image_view": "rqt_image_view",
    "rqt_plot": "rqt_plot",
    "rqt_reconfigure": "rqt_reconfigure",
    "rqt_tf_tree": "rqt_tf_tree",
    "rviz": "rviz",
    "teleop_twist_joy": "teleop_twist_joy",
    "teleop_twist_keyboard": "teleop_twist_keyboard",
    "tf": "tf",
    "tf2_ros": "tf2_ros",
    "turtlebot_teleop": "turtlebot_teleop",
    "turtlesim": "turtlesim",
    "urdf": "urdfdom",
    "urdfdom": "urdfdom",
    "usb_cam": "usb_cam",
    "video_stream_opencv": "video_stream_opencv",
}
"""ROS package → the module here that provides its executables."""


def end_node(session: Session, node: Node, status: int = 0) -> None:
    """``node`` ends by itself, as a ROS executable that exits (map_saver once it has saved):
    it leaves the graph with its exit status; a required node's end ends the launch or run.
    Call on the executor thread (or while starting)."""
    session.finished[node.full_name] = status
    node.shutdown()


def end_when(
    session: Session, node: Node, done: Callable[[], bool], *, period: float = 0.1
) -> None:
    """End ``node`` (:func:`end_node`) once ``done()`` holds — work that finishes on a thread
    of its own (a recorder whose ``--duration`` passed, a player at the end of its bag) —
    looking every ``period`` seconds of graph time."""

    def check() -> None:
        if done() and not node.closed:
            end_node(session, node)

    node.timer(period, check)


def _table(package: str, attribute: str, empty: Any) -> Any:
    """A table of ``package``'s node module (``EXECUTABLES``, ``JOINING``, ``FILES`` …);
    ``empty`` for a package belvedere has no module for, or a module without that table."""
    if package not in MODULES:
        return empty
    module = importlib.import_module(f"belvedere.nodes.{MODULES[package]}")
    return getattr(module, attribute, empty)


def find(package: str, executable: str) -> Starter | None:
    """The starter of ``package``'s ``executable``, if belvedere has it."""
    table: dict[str, Starter] = _table(package, "EXECUTABLES", {})
    return table.get(executable)


def joins_running_graph(package: str, executable: str) -> bool:
    """Whether ``run`` starts ``executable`` on a graph that is already running (as a ROS
    client joins the master), rather than on a graph of its own: true for the nodes whose
    module lists it in ``JOINING`` (rviz, map_saver, robot_state_publisher…), not for the
    simulators, which make the graph's clock."""
    return executable in _module_set(package, "JOINING")


def anonymous(package: str, executable: str) -> bool:
    """Whether ``executable`` names itself anonymously when nothing renames it (roscpp's
    ``AnonymousName``: ``rosrun rviz rviz`` is ``/rviz_<nanoseconds>``), as the module's
    ``ANONYMOUS`` says."""
    return executable in _module_set(package, "ANONYMOUS")


def node_name(package: str, executable: str) -> str:
    """The name ``executable`` gives its node when nothing renames it: what its ``ros::init``
    says, as the module's ``NAMES`` has it (``turtlesim_node`` is ``turtlesim``), else the
    executable's own name."""
    names: dict[str, str] = _table(package, "NAMES", {})
    return names.get(executable, executable.removesuffix(".py"))


def _module_set(package: str, attribute: str) -> frozenset[str]:
    found: frozenset[str] = _table(package, attribute, frozenset())
    return found


def transforms(spec: NodeSpec, param: ParamLookup) -> list[tuple[str, str]]:
    """The (parent, child) frames the node of ``spec`` will publish transforms between, for
    the nodes that publish fixed ones (static publishers, localizers, mappers); frames without
    a leading ``/``. A node that cannot say (bad arguments) claims none: its start says why."""
    claims: dict[str, TransformClaim] = _table(spec.pkg, "TRANSFORMS", {})
    claim = claims.get(spec.type)
    if claim is None:
        return []
    try:
        pairs = claim(spec, param)
    except (ValueError, BelvedereError):
        return []
    return [(parent.lstrip("/"), child.lstrip("/")) for parent, child in pairs]


def files(spec: NodeSpec) -> list[tuple[str, str]]:
    """The (kind, path) of each file the node of ``spec`` will read (an rviz config, a world,
    a map), as its module's ``FILES`` says; none for a node that cannot say (bad arguments:
    its start says why)."""
    claims: dict[str, FileClaim] = _table(spec.pkg, "FILES", {})
    claim = claims.get(spec.type)
    if claim is None:
        return []
    try:
        return claim(spec)
    except (ValueError, BelvedereError):
        return []


def executables(package: str) -> list[str]:
    """The executables belvedere has for ``package`` (none if it has not the package)."""
    return sorted(_table(package, "EXECUTABLES", {}))


def package_names() -> list[str]:
    return sorted(MODULES)
