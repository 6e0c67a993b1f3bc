"""The newest-only outbox: bulky messages of queue-size-1/2 topics, sent from a thread of
their own (see :mod:`belvedere.graph._zenoh`), and what the transport did with each topic's
messages.
"""

from __future__ import annotations

import logging
import threading
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Final

from belvedere.graph._endpoints import Topic

__all__ = ["BULKY", "NEWEST_ONLY", "TopicStats"]

logger = logging.getLogger("belvedere.transport")

NEWEST_ONLY: Final = 2
"""Publishers with a queue size up to this (and above 0) want only their newest messages sent."""


@dataclass(slots=True)
class TopicStats:
    """What the transport did with one topic's messages (for benchmarks and ``topic hz``)."""

    sent: int = 0
    """Messages handed to Zenoh."""
    superseded: int = 0
    """Messages not sent because newer ones came before the link was free."""
    serialize_s: float = 0.0
    """Time spent serializing sent messages."""
    put_s: float = 0.0
    """Time spent handing them to Zenoh (blocked while the link is congested)."""
    received: int = 0
    """Samples that arrived from other processes."""
    skipped: int = 0
    """Samples dropped unread because newer ones arrived before the subscribers were ready."""


BULKY: Final = 64 * 1024
"""Bytes of a message's ``data`` array from which sending it takes long enough to matter."""


def _bulky(msg: Any) -> bool:
    """An image, point cloud or map: a ``data`` array of :data:`BULKY` bytes or more."""
    data = getattr(msg, "data", None)
    return int(getattr(data, "nbytes", 0)) >= BULKY


class _Outbox:
    """The newest messages of queue-size-1/2 topics, sent from a thread of their own."""

    def __init__(
        self, put: Callable[[Topic, Any, bytes], None], stats: Callable[[str], TopicStats]
    ):
        self._put = put
        self._stats = stats
        self._queues: dict[str, tuple[Topic, deque[Any]]] = {}
        self._ready: deque[str] = deque()
        self._busy = False
        self._cond = threading.Condition()
        self._closed = False
        self._thread: threading.Thread | None = None

    def push(self, topic: Topic, msg: Any, stamp: bytes, depth: int) -> None:
        with self._cond:
            if self._closed:
                return
            entry = self._queues.get(topic.name)
            if entry is None or entry[1].maxlen != depth:
                old = entry[1] if entry is not None else ()
                entry = self._queues[topic.name] = (topic, deque(old, maxlen=depth))
            queue = entry[1]
            if len(queue) == depth:
                self._stats(topic.name).superseded += 1
            queue.append((msg, stamp))
            if topic.name not in self._ready:
                self._ready.append(topic.name)
            if self._thread is None:
                self._thread = threading.Thread(
                    target=self._run, name="belvedere-outbox", daemon=True
                )
                self._thread.start()
            self._cond.notify()

    def _run(self) -> None:
        while True:
            with self._cond:
                self._busy = False
                self._cond.notify_all()
                while not self._ready and not self._closed:
                    self._cond.wait()
                if not self._ready:
                    return
                name = self._ready.popleft()
                topic, queue = self._queues[name]
                msg, stamp = queue.popleft()
                if queue:
                    self._ready.append(name)
                self._busy = True
            try:
                self._put(topic, msg, stamp)
            except Exception as err:  # noqa: BLE001 (a closed session, a refused message)
                logger.debug("not sent on %s: %s", topic.name, err)

    def flush(self, timeout: float) -> bool:
        """Wait until everything queued is sent (True), or ``timeout`` seconds."""
        with self._cond:
            return self._cond.wait_for(lambda: not self._ready and not self._busy, timeout)

    def close(self, timeout: float = 2.0) -> None:
        self.flush(timeout)
        with self._cond:
            self._closed = True
            self._cond.notify_all()
