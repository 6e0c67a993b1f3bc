"""``init_node`` and the node-wide calls of rospy's client API: spin, names, argv,
shutdown hooks, graph introspection."""

from __future__ import annotations

import atexit
import contextlib
import os
import signal
import sys
import threading
import time
from collections.abc import Callable
from types import FrameType
from typing import Any

from belvedere.errors import BelvedereError
from belvedere.graph import Graph, ZenohTransport
from belvedere.ros1.rospy import _logging, _state, _topics
from belvedere.ros1.rospy._exceptions import ROSException, ROSInitException

__all__ = [
    "get_caller_id",
    "get_name",
    "get_namespace",
    "get_node_uri",
    "get_published_topics",
    "init_node",
    "myargv",
    "on_shutdown",
    "remap_name",
    "resolve_name",
    "spin",
]

_init_args: tuple[Any, ...] | None = None


def init_node(
    name: str,
    argv: list[str] | None = None,
    anonymous: bool = False,
    log_level: int | None = None,
    disable_rostime: bool = False,
    disable_rosout: bool = False,
    disable_signals: bool = False,
    xmlrpc_port: int = 0,
    tcpros_port: int = 0,
) -> None:
    """Join the graph as node ``name`` (``__name:=`` and ``__ns:=`` in argv override it)."""
    global _init_args
    if argv is None:
        argv = sys.argv
    else:
        _state.reload_args(list(argv))
    if not name:
        msg = "name must not be empty"
        raise ValueError(msg)
    if "/" in name:
        msg = "namespaces are not allowed in node names"
        raise ValueError(msg)
    args = (name, argv, anonymous, log_level, disable_rostime, disable_signals)
    if _init_args is not None:
        if _init_args != args:
            msg = (
                f"rospy.init_node() has already been called with different arguments: {_init_args}"
            )
            raise ROSException(msg)
        return
    _init_args = args
    mappings = _state.mappings()
    if mappings.name:
        name, anonymous = mappings.name, False
    if anonymous:
        name = f"{name}_{os.getpid()}_{int(time.time() * 1000)}"
    namespace = _state.namespace()
    try:
        transport = ZenohTransport(serve_params=False)
    except BelvedereError as err:
        msg = f"cannot join the graph: {err.message}"
        raise ROSInitException(msg) from None
    graph = Graph(sim_time=False, transport=transport, clock_hz=None)
    if not disable_signals and threading.current_thread() is threading.main_thread():
        _register_signals()
    # Runs before the transport's own exit hook (those run last-registered first), so
    # on_shutdown hooks can still publish when the script ends.
    threading._register_atexit(_at_exit)  # type: ignore[attr-defined]
    atexit.register(_at_exit)
    node = graph.create_node(name, namespace=namespace, remappings=mappings.remappings)
    graph.start(rtf=None)
    level = log_level if log_level is not None else _logging.INFO
    runtime = _state.Runtime(graph=graph, node=node, transport=transport, log_level=level)
    _state.set_runtime(runtime, name, namespace)
    for key, value in mappings.params.items():
        from belvedere.ros1.rospy._params import set_param

        set_param(f"~{key}", value)
    if not disable_rosout:
        runtime.rosout = runtime.run_on_executor(
            lambda: node.publisher(
                "/rosout", "rosgraph_msgs/Log", latch=True, queue_size=100, seq_rule="rospy"
            )
        )
    if not disable_rostime:
        _start_clock(runtime)
    for action in _topics.take_pending():
        action(runtime)
    threading.Thread(target=_watch_node, args=(runtime,), daemon=True).start()


def _start_clock(runtime: _state.Runtime) -> None:
    from belvedere.ros1.rospy._params import get_param

    try:
        use_sim_time = bool(get_param("/use_sim_time", False))
    except ROSException:
        use_sim_time = False
    if not use_sim_time:
        return
    runtime.sim_time = True
    node = runtime.node

    def on_clock(msg: Any) -> None:
        stamp = msg.clock
        runtime.set_clock(stamp.sec * 1_000_000_000 + stamp.nanosec)

    runtime.run_on_executor(
        lambda: node.subscribe("/clock", "rosgraph_msgs/Clock", on_clock, queue_size=1)
    )


def _watch_node(runtime: _state.Runtime) -> None:
    """A node of the same name started elsewhere replaces this one (as ROS 1's master
    does), or another process asks it to end (rosnode kill): shut down, with rospy's
    reason."""
    stop = _state.shutdown_event()
    while not stop.wait(0.2):
        if runtime.node.closed:
            asked = runtime.node.shutdown_request
            if asked is not None:  # rosnode kill, as rospy's handler of the request says it
                caller, why = asked
                sys.stdout.write(f"shutdown request: {why}\n")
                sys.stdout.flush()
                _state.signal_shutdown(f"external shutdown request from [{caller}]: {why}")
                return
            name = _state.caller_id()
            _logging.log(_logging.WARN, "Shutdown request received.", ())
            _logging.log(
                _logging.WARN,
                "Reason given for shutdown: [[%s] Reason: new node registered with same name]",
                (name,),
            )
            _state.signal_shutdown(f"[{name}] Reason: new node registered with same name")
            return


def _at_exit() -> None:
    _state.signal_shutdown("atexit")


_previous: dict[int, Any] = {}


def _on_signal(signum: int, frame: FrameType | None) -> None:
    _state.signal_shutdown(f"signal-{signum}")
    previous = _previous.get(signum)
    if callable(previous):
        # rospy swallows the interrupt: loops end through is_shutdown()
        with contextlib.suppress(KeyboardInterrupt):
            previous(signum, frame)


def _register_signals() -> None:
    for signum in (signal.SIGINT, signal.SIGTERM):
        _previous[signum] = signal.getsignal(signum)
        signal.signal(signum, _on_signal)


def spin() -> None:
    """Block until shutdown."""
    if not _state.is_initialized():
        msg = "client code must call rospy.init_node() first"
        raise ROSInitException(msg)
    stop = _state.shutdown_event()
    try:
        while not stop.wait(0.5):
            pass
    except KeyboardInterrupt:
        _state.signal_shutdown("keyboard interrupt")


def on_shutdown(h: Callable[[], Any]) -> None:
    _state.add_client_hook(h)


def myargv(argv: list[str] | None = None) -> list[str]:
    """``argv`` without ROS's ``name:=value`` arguments."""
    return [a for a in (sys.argv if argv is None else argv) if ":=" not in a]


def get_name() -> str:
    return _state.caller_id()


get_caller_id = get_name


def get_namespace() -> str:
    ns = _state.namespace()
    return ns if ns.endswith("/") else ns + "/"


def resolve_name(name: str, caller_id: str | None = None) -> str:
    return _state.resolve(name)


def remap_name(name: str, caller_id: str | None = None, resolved: bool = True) -> str:
    return _state.resolve(name)


def get_node_uri() -> str | None:
    runtime = _state.current()
    if runtime is None or runtime.transport is None:
        return None
    return f"zenoh/{runtime.transport.endpoint}"


def get_published_topics(namespace: str = "/") -> list[list[str]]:
    """``[[topic, type], …]`` of every topic someone publishes, under ``namespace``."""
    runtime = _state.required()
    if runtime.transport is None:
        found = {(t.name, t.type) for t in runtime.graph.topics.values() if t.publishers}
    else:
        info = runtime.transport.info(timeout=1.0)
        found = {(name, kind) for name, pubs in info.publishers.items() for kind, _ in pubs}
    prefix = namespace.rstrip("/") + "/"
    from belvedere.msgs import short

    return [[name, short(kind)] for name, kind in sorted(found) if name.startswith(prefix)]
