"""rospy's ``Publisher`` and ``Subscriber`` over belvedere's graph.

Messages are the genpy-like classes of :mod:`belvedere.ros1`; the graph carries the type
store's objects, so a publication converts once (``to_store``) and a subscriber converts what
it receives (``from_store``). Each subscriber calls its callback on a thread of its own with
its own queue (``queue_size``, oldest dropped), as rospy does.
"""

from __future__ import annotations

import threading
import traceback
import warnings
from collections import deque
from collections.abc import Callable
from typing import Any, TypeVar

from belvedere.errors import BelvedereError
from belvedere.graph import Publisher as GraphPublisher
from belvedere.graph import Subscription
from belvedere.msgs import types
from belvedere.ros1._classes import from_store, to_store
from belvedere.ros1._message import Message
from belvedere.ros1.rospy import _state
from belvedere.ros1.rospy._exceptions import (
    ROSException,
    ROSInterruptException,
    ROSSerializationException,
)

T = TypeVar("T")

__all__ = [
    "Publisher",
    "SubscribeListener",
    "Subscriber",
    "args_kwds_to_message",
    "wait_for_message",
]


class SubscribeListener:
    """rospy's hook for subscribers connecting to a publisher (accepted; never called:
    connections are not per subscriber here)."""

    def peer_subscribe(self, topic_name: str, topic_publish: Any, peer_publish: Any) -> None:
        """A subscriber connected."""

    def peer_unsubscribe(self, topic_name: str, num_peers: int) -> None:
        """A subscriber left."""


def _check_class(data_class: Any) -> str:
    if not isinstance(data_class, type):
        msg = f"data_class [{data_class}] is not a class"
        raise ValueError(msg)
    if not issubclass(data_class, Message):
        msg = f"data_class [{data_class.__name__}] is not a message data class"
        raise ValueError(msg)
    return data_class._type


def _check_name(name: Any) -> str:
    if not isinstance(name, str) or not name:
        msg = "topic name is not a non-empty string"
        raise ValueError(msg)
    return name


def args_kwds_to_message(data_class: type[Message], args: tuple[Any, ...], kwds: Any) -> Any:
    """A message from ``publish``'s (or a service call's) arguments, as rospy builds it."""
    if args and kwds:
        msg = "publish() can be called with arguments or keywords, but not both."
        raise TypeError(msg)
    if kwds:
        return data_class(**kwds)
    if len(args) == 1:
        arg = args[0]
        if getattr(arg, "_md5sum", None) == data_class._md5sum:
            return arg
        if isinstance(arg, Message):
            if not data_class._slot_types:
                msg = f"expected [] but got [{arg._type}]"
                raise TypeError(msg)
            if arg._type != data_class._slot_types[0]:
                msg = f"expected [{data_class._slot_types[0]}] but got [{arg._type}]"
                raise TypeError(msg)
    return data_class(*args)


def seconds_or_none(timeout: Any) -> float | None:
    """A timeout given as seconds or as a Duration."""
    if timeout is None:
        return None
    to_sec = getattr(timeout, "to_sec", None)
    return float(to_sec()) if callable(to_sec) else float(timeout)


class _Topic:
    """What publishers and subscribers share: the name, the class, the unregistering."""

    def __init__(self, name: Any, data_class: Any) -> None:
        self.given_name = _check_name(name)
        self.type = _check_class(data_class)
        self.data_class: type[Message] = data_class
        self.resolved_name = _state.resolve(self.given_name)
        self.name = self.resolved_name  # rospy's .name is the resolved one too
        self.closed = False

    def _register_soon(self) -> None:
        """Register with the node now, or when ``init_node`` makes it: rospy registers the
        topics made before ``init_node`` then."""
        runtime = _state.current()
        if runtime is None:
            _pending_runtime_actions.append(self._register)
        else:
            self._register(runtime)

    def _register(self, runtime: _state.Runtime) -> None:
        raise NotImplementedError

    def get_num_connections(self) -> int:
        raise NotImplementedError


class Publisher(_Topic):
    """rospy.Publisher: ``publish(msg)``, ``publish(field, …)`` or ``publish(field=…)``."""

    def __init__(
        self,
        name: str,
        data_class: type[Message],
        subscriber_listener: Any = None,
        tcp_nodelay: bool = False,
        latch: bool = False,
        headers: Any = None,
        queue_size: int | None = None,
    ) -> None:
        super().__init__(name, data_class)
        if queue_size is None:
            warnings.warn(
                "The publisher should be created with an explicit keyword argument "
                "'queue_size'. Please see http://wiki.ros.org/rospy/Overview/"
                "Publishers%20and%20Subscribers for more information.",
                SyntaxWarning,
                stacklevel=2,
            )
        self.latch = latch
        self.queue_size = queue_size
        self._impl: GraphPublisher | None = None
        self._register_soon()

    def _register(self, runtime: _state.Runtime) -> None:
        node = runtime.node
        self.resolved_name = self.name = node.resolve(self.given_name)
        types().prepare(self.type)  # here, not on the executor, where it would hold others up
        self._impl = _registered(
            runtime,
            lambda: node.publisher(
                self.resolved_name,
                self.type,
                queue_size=self.queue_size or 0,
                latch=self.latch,
                seq_rule="given",
            ),
        )

    def publish(self, *args: Any, **kwds: Any) -> None:
        if self.closed:
            msg = "publish() to an unregistered() handle"
            raise ROSException(msg)
        if self._impl is None:
            msg = "ROS node has not been initialized yet. Please call init_node() first"
            raise ROSException(msg)
        data = args_kwds_to_message(self.data_class, args, kwds)
        self._number(data)
        try:
            converted = to_store(data)
        except (BelvedereError, TypeError, ValueError, AttributeError) as err:
            raise ROSSerializationException(str(err)) from None
        if _state.is_shutdown():
            return
        self._impl.publish(converted)

    def _number(self, data: Any) -> None:
        """rospy's ``header.seq``: per topic in this process, counting from 1 the messages
        that reach a subscriber, written into the caller's message."""
        if not getattr(type(data), "_has_header", False) or not self.get_num_connections():
            return
        with _seq_lock:
            seq = _seqs.get(self.resolved_name, 0) + 1
            _seqs[self.resolved_name] = seq
        data.header.seq = seq

    def get_num_connections(self) -> int:
        impl = self._impl
        if impl is None:
            return 0
        topic = impl.topic
        local = {sub.node.full_name for sub in topic.subscriptions}
        return len(local) + (1 if topic.remote else 0)

    def unregister(self) -> None:
        impl = self._impl
        if impl is not None and not self.closed:
            runtime = _state.current()
            if runtime is not None:
                runtime.run_on_executor(impl.unregister)
        self.closed = True
        self._impl = None


class Subscriber(_Topic):
    """rospy.Subscriber: ``callback(msg)`` or ``callback(msg, callback_args)`` per message."""

    def __init__(
        self,
        name: str,
        data_class: type[Message],
        callback: Any = None,
        callback_args: Any = None,
        queue_size: int | None = None,
        buff_size: int = 65536,
        tcp_nodelay: bool = False,
    ) -> None:
        super().__init__(name, data_class)
        if queue_size == 0:
            msg = "queue size may not be set to zero"
            raise ROSException(msg)
        if queue_size is not None and not isinstance(queue_size, int):
            msg = "queue size must be an integer"
            raise ROSException(msg)
        self.callback = callback
        self.callback_args = callback_args
        self.queue_size = queue_size
        self._queue: deque[Any] = deque(
            maxlen=queue_size if queue_size and queue_size > 0 else None
        )
        self._ready = threading.Condition()
        self._impl: Subscription | None = None
        self._thread: threading.Thread | None = None
        self._register_soon()

    def _register(self, runtime: _state.Runtime) -> None:
        self.resolved_name = self.name = runtime.node.resolve(self.given_name)
        if self.callback is not None:
            self._thread = threading.Thread(
                target=self._dispatch, name=f"subscriber {self.resolved_name}", daemon=True
            )
            self._thread.start()
        node = runtime.node
        depth = self.queue_size if self.queue_size and self.queue_size > 0 else 0
        types().prepare(self.type)  # here, not on the executor, where it would hold others up
        self._impl = _registered(
            runtime,
            lambda: node.subscribe(self.resolved_name, self.type, self._arrived, queue_size=depth),
        )

    def _arrived(self, obj: Any) -> None:
        """On the executor thread: queue the message for this subscriber's thread."""
        if self.callback is None or self.closed:
            return
        with self._ready:
            self._queue.append(obj)
            self._ready.notify()

    def _dispatch(self) -> None:
        stop = _state.shutdown_event()
        while not stop.is_set() and not self.closed:
            with self._ready:
                while not self._queue and not stop.is_set() and not self.closed:
                    self._ready.wait(0.2)
                if not self._queue:
                    continue
                obj = self._queue.popleft()
            self._call(obj)

    def _call(self, obj: Any) -> None:
        callback = self.callback
        try:
            msg = from_store(obj)
            if self.callback_args is not None:
                callback(msg, self.callback_args)
            else:
                callback(msg)
        except Exception:  # noqa: BLE001 (rospy logs a callback's error and goes on)
            from belvedere.ros1.rospy._logging import ERROR, log

            if not _state.is_shutdown():
                log(ERROR, "bad callback: %s\n%s", (callback, traceback.format_exc()))

    def get_num_connections(self) -> int:
        impl = self._impl
        if impl is None:
            return 0
        local = {pub.node.full_name for pub in impl.topic.publishers}
        runtime = _state.current()
        transport = runtime.transport if runtime is not None else None
        if transport is None:
            return len(local)
        return len(local | transport.publisher_nodes(self.resolved_name))

    def unregister(self) -> None:
        impl = self._impl
        self.closed = True
        if impl is not None:
            runtime = _state.current()
            if runtime is not None:
                runtime.run_on_executor(impl.unregister)
        self._impl = None
        with self._ready:
            self._ready.notify_all()


def _registered(runtime: _state.Runtime, make: Callable[[], T]) -> T | None:
    """``make()`` on the executor; the graph's refusal (a topic of another type) as rospy's
    error."""
    try:
        return runtime.run_on_executor(make)
    except BelvedereError as err:
        raise ROSException(err.message) from None


_pending_runtime_actions: list[Any] = []
_seqs: dict[str, int] = {}
_seq_lock = threading.Lock()


def take_pending() -> list[Any]:
    actions = list(_pending_runtime_actions)
    _pending_runtime_actions.clear()
    return actions


def wait_for_message(topic: str, topic_type: type[Message], timeout: Any = None) -> Any:
    """The next message on ``topic`` (waiting at most ``timeout`` wall seconds, a number or
    a Duration)."""
    timeout = seconds_or_none(timeout)
    got: list[Any] = []
    arrived = threading.Event()

    def keep(msg: Any) -> None:
        if not got:
            got.append(msg)
            arrived.set()

    sub = Subscriber(topic, topic_type, keep)
    stop = _state.shutdown_event()
    try:
        import time

        deadline = None if timeout is None else time.monotonic() + timeout
        while not stop.is_set() and not arrived.is_set():
            left = 0.05 if deadline is None else min(0.05, deadline - time.monotonic())
            if left <= 0:
                msg = f"timeout exceeded while waiting for message on topic {topic}"
                raise ROSException(msg)
            arrived.wait(left)
    finally:
        sub.unregister()
    if not got:
        msg = "rospy shutdown"
        raise ROSInterruptException(msg)
    return got[0]
