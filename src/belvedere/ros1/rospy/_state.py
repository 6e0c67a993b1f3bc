"""The process's one rospy node: its graph connection, names, clock and shutdown.

rospy keeps this state per process (one ``init_node`` per process); so does this module.
User callbacks never run on the graph's executor thread — subscriptions and services hand
their work to threads of their own, as rospy's connections do — so the executor is always
free to move the clock and deliver messages, even while a callback sleeps.
"""

from __future__ import annotations

import os
import sys
import threading
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, TypeVar

from belvedere.errors import BelvedereError
from belvedere.graph import (
    NS,
    Graph,
    Node,
    Publisher,
    RosArgs,
    ZenohTransport,
    parse_ros_args,
)
from belvedere.graph import resolve_name as _resolve
from belvedere.ros1.rospy._exceptions import ROSInitException

T = TypeVar("T")

__all__ = [
    "Runtime",
    "add_client_hook",
    "add_preshutdown_hook",
    "add_shutdown_hook",
    "caller_id",
    "current",
    "is_initialized",
    "is_shutdown",
    "is_shutdown_requested",
    "mappings",
    "namespace",
    "required",
    "resolve",
    "shutdown_event",
    "signal_shutdown",
]


@dataclass
class Runtime:
    """The initialized node: graph, node, transport and clock."""

    graph: Graph
    node: Node
    transport: ZenohTransport | None
    log_level: int
    sim_time: bool = False
    clock_ns: int = 0
    clock: threading.Condition = field(default_factory=threading.Condition)
    rosout: Publisher | None = None

    def now_ns(self) -> int:
        if self.sim_time:
            return self.clock_ns
        return time.time_ns()

    def set_clock(self, ns: int) -> None:
        with self.clock:
            self.clock_ns = ns
            self.clock.notify_all()

    def run_on_executor(self, fn: Callable[[], T], timeout: float = 10.0) -> T | None:
        """``fn()`` run on the executor thread, its error raised here (a barrier too: what
        was posted before it, e.g. publications, has been handed on when it returns).
        None if the executor has stopped or did not get to it in time."""
        if self.graph.on_executor_thread():
            return fn()
        if self.graph.executor.stopped:
            return None
        try:
            return self.graph.executor.call(fn, timeout)
        except TimeoutError:
            return None


_runtime: Runtime | None = None
_args: RosArgs = parse_ros_args(sys.argv[1:])
_namespace: str = "/"
_caller_id: str = "/unnamed"
_lock = threading.RLock()
_shutdown = threading.Event()
_in_shutdown = False
_client_hooks: list[Callable[[], Any]] = []
_preshutdown_hooks: list[Callable[[str], Any]] = []
_shutdown_hooks: list[Callable[[str], Any]] = []


def _initial_namespace() -> str:
    ns = _args.namespace or os.environ.get("ROS_NAMESPACE") or "/"
    return "/" + "/".join(p for p in ns.split("/") if p)


_namespace = _initial_namespace()


def current() -> Runtime | None:
    return _runtime


def required() -> Runtime:
    """The runtime, or rospy's error for code that runs before ``init_node``."""
    if _runtime is None:
        msg = "client code must call rospy.init_node() first"
        raise ROSInitException(msg)
    return _runtime


def set_runtime(runtime: Runtime, name: str, namespace: str) -> None:
    global _runtime, _caller_id, _namespace
    _runtime = runtime
    _namespace = namespace
    _caller_id = _resolve(name, namespace=namespace)


def reload_args(argv: list[str]) -> None:
    """``init_node(argv=…)``: the mappings come from that argv instead."""
    global _args, _namespace
    _args = parse_ros_args(argv[1:])
    _namespace = _initial_namespace()


def mappings() -> RosArgs:
    return _args


def is_initialized() -> bool:
    return _runtime is not None


def caller_id() -> str:
    return _caller_id


def namespace() -> str:
    return _namespace


def _remaps(namespace: str, node: str) -> dict[str, str]:
    out: dict[str, str] = {}
    for key, value in _args.remappings.items():
        try:
            out[_resolve(key, namespace=namespace, node=node)] = _resolve(
                value, namespace=namespace, node=node
            )
        except BelvedereError:
            continue  # a malformed mapping: ROS ignores it too
    return out


def resolve(name: str, *, remap: bool = True) -> str:
    """rospy.resolve_name: relative to the node's namespace, ``~`` to its name, remapped."""
    node = _caller_id
    namespace = _namespace
    if not name:
        return namespace if namespace.endswith("/") else namespace + "/"
    if name == "~":
        return node + "/"  # rospy keeps the separator of a bare private name
    remappings = _remaps(namespace, node) if remap else None
    return _resolve(name, namespace=namespace, node=node, remappings=remappings)


def remappings_for(namespace: str, node: str) -> dict[str, str]:
    return _remaps(namespace, node)


# --- shutdown ----------------------------------------------------------------------------------


def is_shutdown() -> bool:
    return _shutdown.is_set()


def is_shutdown_requested() -> bool:
    """Shutdown has begun (its hooks may still be running) or is over."""
    return _in_shutdown or _shutdown.is_set()


def shutdown_event() -> threading.Event:
    return _shutdown


def _check_callable(hook: object) -> None:
    if not callable(hook):
        msg = f"shutdown hook [{hook}] must be a function or callable object: {type(hook)}"
        raise TypeError(msg)


def add_client_hook(hook: Callable[[], Any]) -> None:
    """rospy.on_shutdown: ``hook()`` runs when shutdown starts (at once if it is over)."""
    _check_callable(hook)
    if _shutdown.is_set():
        hook()
        return
    with _lock:
        _client_hooks.append(hook)


def add_preshutdown_hook(hook: Callable[[str], Any]) -> None:
    _check_callable(hook)
    if _shutdown.is_set():
        hook("already shutdown")
        return
    with _lock:
        _preshutdown_hooks.append(hook)


def add_shutdown_hook(hook: Callable[[str], Any]) -> None:
    _check_callable(hook)
    if _shutdown.is_set():
        hook("already shutdown")
        return
    with _lock:
        _shutdown_hooks.append(hook)


def signal_shutdown(reason: str) -> None:
    """Shut the node down, as rospy does: ``on_shutdown`` hooks (while publishing still
    works), then pre-shutdown hooks, then the flag, then the node leaves the graph."""
    global _in_shutdown
    if _shutdown.is_set() or _in_shutdown:
        return
    with _lock:
        if _shutdown.is_set() or _in_shutdown:
            return
        _in_shutdown = True
        for client_hook in list(_client_hooks):
            try:
                client_hook()
            except Exception:  # noqa: BLE001 (rospy prints a hook's error and goes on)
                traceback.print_exc()
        _client_hooks.clear()
        for pre_hook in list(_preshutdown_hooks):
            try:
                pre_hook(reason)
            except Exception:  # noqa: BLE001
                traceback.print_exc()
        _preshutdown_hooks.clear()
        runtime = _runtime
        if runtime is not None:
            # What the hooks published is on its way before the node leaves.
            runtime.run_on_executor(lambda: None)
            if runtime.transport is not None:
                runtime.transport.flush(2.0)
        _shutdown.set()
        with_clock = runtime.clock if runtime is not None else None
        if with_clock is not None:
            with with_clock:
                with_clock.notify_all()
        for hook in list(_shutdown_hooks):
            try:
                hook(reason)
            except Exception as err:  # noqa: BLE001
                sys.stderr.write(f"signal_shutdown hook error[{err}]\n")
        _shutdown_hooks.clear()
        if runtime is not None:
            # The node leaves the graph now; the session closes at exit, on the main thread
            # (Zenoh's threads must not outlive the interpreter's finalization).
            runtime.run_on_executor(runtime.node.shutdown)
            runtime.graph.executor.stop()


def clock_ns() -> int:
    return required().now_ns()


def wall_ns() -> int:
    return time.time_ns()


SECOND = NS
