"""Recording: what ``rosbag record`` does with the messages it receives.

:class:`Recorder` writes samples to bag files as the options say — the file's name,
splitting by size or duration, per-topic limits, stopping after a duration — on a thread of
its own, writing a chunk at least every second. Samples come from a source:

- :class:`GraphRecording`: subscriptions of a node in this process (a launch file's
  ``rosbag/record``); messages arrive as the store's objects, stamped with the graph's time
  when they are delivered.
- :class:`TapRecording`: the transport's raw messages from other processes (``belvedere bag
  record``); nothing is deserialized to be recorded to MCAP. Stamps are the graph's time at
  receipt, as rosbag's: in simulated time the time each message was published at (which
  the transport sends with it; delivery takes no simulated time) — or, from a publisher in
  wall time, the last ``/clock`` — and otherwise the wall clock at receipt.
"""

from __future__ import annotations

import logging
import queue
import threading
import time
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from datetime import datetime
from pathlib import Path
from typing import Any, Final

from belvedere.bags._files import BagWriter, create_writer
from belvedere.bags._model import BagError, encode, transcode
from belvedere.bags._options import RecordOptions, bag_name
from belvedere.errors import BelvedereError
from belvedere.graph import GraphError, LatchedOnce, Node, Sent, ZenohTransport
from belvedere.msgs import MessageTypeError, types

__all__ = ["GraphRecording", "Recorder", "Sample", "TapRecording"]

logger = logging.getLogger("belvedere.bags")

FLUSH_PERIOD: Final = 1.0
"""Wall seconds between chunks written to disk (at most this much is lost to a kill -9)."""
CLOCK: Final = "/clock"
STRAGGLER_WAIT: Final = 0.5
"""Wall seconds a recording with ``--duration`` waits, once the clock passed its end, for
messages stamped before the end."""


@dataclass(slots=True)
class Sample:
    """One message to record."""

    topic: str
    msgtype: str | None
    """The store's name; None until the source knows it."""
    stamp_ns: int | None
    """The graph's time at receipt; None until the source knows it."""
    payload: Any
    """A store object, or CDR bytes (``cdr``)."""
    cdr: bool
    wall_ns: int = 0
    latching: bool = False
    callerid: str | None = None
    latch: tuple[str, int] | None = None
    """Which latching publisher's publication it is (its number): recorded once, whether it
    came through the tap or as the reply to the recorder's question for latched messages."""
    sim: bool = False
    """Its stamp is the simulated time its publisher sent it at."""


class Source:
    """Where samples come from; the recorder asks it to finish them (their stamps, types)."""

    def begin(self) -> None:
        """Start delivering (the recorder's first file is open)."""

    def ready(self, sample: Sample) -> Iterable[Sample]:
        return (sample,)

    def tick(self) -> Iterable[Sample]:
        """Samples that waited and can go now (called at least every second)."""
        return ()

    def now_ns(self) -> int | None:
        """The graph's time now, as far as the source knows (None: not known yet)."""
        return None

    def close(self) -> None:
        """Stop delivering."""


@dataclass
class _File:
    writer: BagWriter
    final: Path
    start_ns: int | None = None
    connections: dict[str, Any] = field(default_factory=dict)


class Recorder:
    """Writes samples to bag files as ``options`` say, on a thread of its own."""

    def __init__(
        self,
        options: RecordOptions,
        *,
        directory: Path | None = None,
        on_progress: Callable[[float], None] | None = None,
    ) -> None:
        self.options = options
        self.directory = directory or Path()
        self.on_progress = on_progress
        """Called with the seconds recorded so far (with ``--duration``)."""
        self.source: Source = Source()
        self.counts: dict[str, int] = {}
        """Messages written, per topic."""
        self.files: list[Path] = []
        """Every file written (whole ones; the last while recording is ``.active``)."""
        self.finished = threading.Event()
        """Set once the duration, size or limits ended the recording."""
        self.error: BaseException | None = None
        self._queue: queue.SimpleQueue[Sample | None] = queue.SimpleQueue()
        self._file: _File | None = None
        self._split = 0 if options.split else None
        self._latched: dict[str, Sample] = {}
        self._start_ns: int | None = None
        self._end_seen: float | None = None
        self._thread: threading.Thread | None = None
        self._active: Path | None = None
        self.written = 0

    # --- control (any thread) -------------------------------------------------------------
    def start(self, source: Source | None = None) -> None:
        """Open the first file and start writing what :meth:`put` is given."""
        if source is not None:
            self.source = source
        self._open()
        self.source.begin()
        self._thread = threading.Thread(target=self._run, name="belvedere-record", daemon=True)
        self._thread.start()

    def put(self, sample: Sample) -> None:
        self._queue.put(sample)

    def stop(self) -> None:
        """Write what was given so far, close the file (its index written), and return."""
        self.source.close()
        if self._thread is not None:
            self._queue.put(None)
            self._thread.join()
            self._thread = None
        if self.error is not None:
            error, self.error = self.error, None
            if isinstance(error, OSError):
                where = error.filename or self._active or "the bag"
                msg = f"cannot write {where}: {error.strerror or error}"
                raise BagError(msg) from None
            raise error

    @property
    def path(self) -> Path | None:
        """The file being written (its final name)."""
        return self._file.final if self._file is not None else None

    # --- the writing thread ---------------------------------------------------------------
    def _run(self) -> None:
        last_flush = time.monotonic()
        try:
            while True:
                timeout = max(0.0, last_flush + FLUSH_PERIOD - time.monotonic())
                try:
                    sample = self._queue.get(timeout=timeout)
                except queue.Empty:
                    sample = None
                    for ready in self.source.tick():
                        self._write(ready)
                else:
                    if sample is None:
                        break
                    for ready in self.source.ready(sample):
                        self._write(ready)
                self._check_time()
                now = time.monotonic()
                if now - last_flush >= FLUSH_PERIOD:
                    for ready in self.source.tick():
                        self._write(ready)
                    if self._file is not None:
                        self._file.writer.flush()
                    last_flush = now
            while True:  # what came before the stop
                try:
                    sample = self._queue.get_nowait()
                except queue.Empty:
                    break
                if sample is not None:
                    for ready in self.source.ready(sample):
                        self._write(ready)
            for ready in self.source.tick():
                self._write(ready)
        except BaseException as err:  # noqa: BLE001 (reported by stop())
            self.error = err
            self.finished.set()
        finally:
            try:
                self._close()
            except OSError as err:
                self.error = self.error or err
                self.finished.set()

    def _write(self, sample: Sample) -> None:
        if self.finished.is_set() or sample.msgtype is None or sample.stamp_ns is None:
            return
        options = self.options
        topic = sample.topic
        count = self.counts.get(topic, 0)
        if options.limit is not None and count >= options.limit:
            return
        stamp = sample.stamp_ns
        if self._start_ns is None:
            self._start_ns = stamp
        file = self._file
        if file is None:
            return
        if file.start_ns is None:
            file.start_ns = stamp
        if options.duration is not None and (stamp - file.start_ns) / 1e9 > options.duration:
            if not options.split:
                self._done()
                return
            self._next_file(stamp)
            file = self._file
            assert file is not None
        self._put(file, sample)
        self.counts[topic] = count + 1
        self.written += 1
        if sample.latching:
            self._latched[topic] = sample
        if self.on_progress is not None and options.duration is not None:
            self.on_progress(min(options.duration, (stamp - (file.start_ns or stamp)) / 1e9))
        if options.size is not None and file.writer.size >= options.size:
            if options.split:
                self._next_file(None)
            else:
                self._done()
                return
        if (
            options.limit is not None
            and not (options.all or options.regex)
            and all(self.counts.get(t, 0) >= options.limit for t in options.topics)
        ):
            self._done()

    def _check_time(self) -> None:
        """Stop once ``--duration`` of the graph's time passed, messages or none — after
        ``STRAGGLER_WAIT`` more wall seconds: ``/clock`` travels apart from the messages, so
        the clock can pass the end while messages stamped before it are still on their way
        (a message stamped after the end stops the recording at once, in :meth:`_write`)."""
        options = self.options
        file = self._file
        if options.duration is None or options.split or file is None or file.start_ns is None:
            return
        now = self.source.now_ns()
        if now is None or (now - file.start_ns) / 1e9 <= options.duration:
            return
        if self._end_seen is None:
            self._end_seen = time.monotonic()
        elif time.monotonic() - self._end_seen >= STRAGGLER_WAIT:
            self._done()

    def _put(self, file: _File, sample: Sample) -> None:
        writer = file.writer
        assert sample.msgtype is not None
        assert sample.stamp_ns is not None
        conn = file.connections.get(sample.topic)
        if conn is None:
            conn = file.connections[sample.topic] = writer.add_connection(
                sample.topic, sample.msgtype, callerid=sample.callerid, latching=sample.latching
            )
        if sample.cdr:
            data = transcode(sample.payload, sample.msgtype, "cdr", writer.encoding)
        else:
            data = encode(sample.payload, writer.encoding)
        writer.write(conn, sample.stamp_ns, data)

    def _done(self) -> None:
        self.finished.set()

    # --- files ----------------------------------------------------------------------------
    def _open(self) -> None:
        name = self.directory / bag_name(self.options, datetime.now(), self._split)
        active = name.with_name(name.name + ".active")
        active.unlink(missing_ok=True)
        writer = create_writer(
            active, compression=self.options.compression, chunk_size=self.options.chunk_size
        )
        self._file = _File(writer, name)
        self._active = active
        if not self.options.quiet:
            logger.info("Recording to '%s'.", name)

    def _close(self) -> None:
        file, self._file = self._file, None
        if file is None:
            return
        try:
            file.writer.close()
        except OSError as err:
            err.filename = err.filename or str(file.writer.path)
            raise
        file.writer.path.replace(file.final)
        self.files.append(file.final)

    def _next_file(self, stamp: int | None) -> None:
        self._close()
        assert self._split is not None
        self._split += 1
        limit = self.options.max_splits
        if limit is not None:
            while len(self.files) >= limit:
                old = self.files.pop(0)
                old.unlink(missing_ok=True)
                if not self.options.quiet:
                    logger.info("Deleting '%s'.", old)
        self._open()
        assert self._file is not None
        self._file.start_ns = stamp
        if self.options.repeat_latched:
            for sample in self._latched.values():
                self._put(self._file, sample)


# --- sources ---------------------------------------------------------------------------------


class GraphRecording(Source):
    """Records through subscriptions of ``node`` (in this process), discovering topics as
    they appear when the options ask for all (or regular expressions)."""

    def __init__(self, node: Node, recorder: Recorder, *, poll: float = 0.5) -> None:
        self.node = node
        self.recorder = recorder
        self.options = recorder.options
        self._subscribed: set[str] = set()
        self._closed = False
        self._remote: dict[str, str] = {}
        self._watch: Any = None
        self._seen: Callable[[str, str, str, bool], None] | None = None
        graph = node.graph
        if isinstance(graph.transport, ZenohTransport):

            def seen(topic: str, type_name: str, _node: str, alive: bool) -> None:
                if alive and topic not in self._remote:
                    self._remote[topic] = type_name
                    graph.executor.post(self.refresh)

            self._seen = seen
        self._poll = poll

    def begin(self) -> None:
        transport = self.node.graph.transport
        if isinstance(transport, ZenohTransport) and self._seen is not None:
            self._watch = transport.watch_publishers(self._seen)
        self.refresh()
        self.node.timer(self._poll, self.refresh)

    def refresh(self) -> None:
        """Subscribe to the wanted topics that exist now (executor thread)."""
        if self._closed:
            return
        graph = self.node.graph
        found = {name: t.type for name, t in list(graph.topics.items()) if t.publishers}
        for name, type_name in list(self._remote.items()):
            found.setdefault(name, type_name)
        for name in self.options.topics if not (self.options.all or self.options.regex) else ():
            topic = graph.topics.get(name)
            if topic is not None:
                found.setdefault(name, topic.type)
        for name, type_name in sorted(found.items()):
            if name in self._subscribed or not self.options.wants(name):
                continue
            self._subscribe(name, type_name)

    def _subscribe(self, name: str, type_name: str) -> None:
        self._subscribed.add(name)
        try:
            self._subscribe_to(name, type_name)
        except BelvedereError as err:
            logger.warning("not recording %s: %s", name, err.message)

    def _subscribe_to(self, name: str, type_name: str) -> None:
        graph = self.node.graph
        topic = graph.topics.get(name)
        latching = topic is not None and any(p.latch for p in topic.publishers)
        callers = sorted(p.node.full_name for p in topic.publishers) if topic else []
        callerid = callers[0] if callers else None
        if not self.options.quiet:
            logger.info("Subscribing to %s", name)
        recorder = self.recorder
        full = types().resolve(type_name)

        def received(msg: Any) -> None:
            if self._closed:
                return
            recorder.put(Sample(name, full, graph.now_ns(), msg, False, 0, latching, callerid))

        self.node.subscribe(name, full, received, queue_size=0)

    def now_ns(self) -> int | None:
        return self.node.graph.now_ns()

    def close(self) -> None:
        self._closed = True
        if self._watch is not None:
            self._watch.undeclare()
            self._watch = None


class TapRecording(Source):
    """Records what other processes publish, as the transport receives it (CDR bytes)."""

    WALL_WAIT: Final = 1.0
    """Seconds to wait for ``/clock`` before stamping with the wall clock, when no graph
    says whether its time is simulated."""
    DETAILS_WAIT: Final = 3.0
    """Seconds a message may wait for its publisher's type and latching to be known."""

    def __init__(self, transport: ZenohTransport, recorder: Recorder) -> None:
        self.transport = transport
        self.recorder = recorder
        self.options = recorder.options
        self._types: dict[str, str] = {}
        self._callers: dict[str, set[str]] = {}
        self._latching: dict[str, bool] = {}
        self._announced: set[str] = set()
        self._pending: deque[Sample] = deque()
        self._latched_recorded: dict[str, LatchedOnce] = {}
        self._clock_ns: int | None = None
        self._sim_now = 0
        """The latest simulated time a message was sent at."""
        self._sim_time: bool | None = self._ask_sim_time()
        self._closed = False
        self._taps: list[Any] = []
        self._watch: Any = None

    def begin(self) -> None:
        put = self.recorder.put
        transport = self.transport
        options = self.options

        def arrived(topic: str, data: bytes, sent: Sent) -> None:
            # Published in simulated time: that is the graph's time it arrived at (delivery
            # takes no simulated time), exact whatever order the topics' taps deliver in.
            when = sent.stamp
            stamp = when[1] if when is not None and when[0] else None
            wall = time.time_ns()
            sim = stamp is not None
            put(Sample(topic, None, stamp, data, True, wall, sim=sim, latch=sent.latch))

        if options.all or options.regex:
            self._taps.append(transport.tap(None, arrived))
        else:
            for topic in options.topics:
                self._taps.append(transport.tap(topic, arrived))
            if CLOCK not in options.topics:
                self._taps.append(transport.tap(CLOCK, arrived))
        self._watch = transport.watch_publishers(self._publisher)

    def _ask_sim_time(self) -> bool | None:
        try:
            value = self.transport.param_request({"op": "get", "name": "/use_sim_time"}, 0.5)
        except GraphError:
            return None  # no graph holds parameters (yet)
        return bool(value)

    # --- discovery (Zenoh's thread) -------------------------------------------------------
    def _publisher(self, topic: str, type_name: str, node: str, alive: bool) -> None:
        if not alive or self._closed:
            return
        try:
            full = types().resolve(type_name)
        except MessageTypeError:
            logger.warning("not recording %s: unknown type %s", topic, type_name)
            return
        self._callers.setdefault(topic, set()).add(node)
        first = topic not in self._types
        self._types.setdefault(topic, full)
        if first and self.options.wants(topic):
            threading.Thread(target=self._fetch_latched, args=(topic,), daemon=True).start()

    def _fetch_latched(self, topic: str) -> None:
        latched = self.transport.latched_raw(topic)
        self._latching[topic] = bool(latched)
        for data, sent in latched:
            wall = time.time_ns()
            self.recorder.put(Sample(topic, None, None, data, True, wall, latch=sent.latch))

    # --- the recorder's thread ------------------------------------------------------------
    def ready(self, sample: Sample) -> Iterable[Sample]:
        topic = sample.topic
        if topic == CLOCK:
            self._clock(sample.payload)
        if sample.sim:
            assert sample.stamp_ns is not None
            if self._sim_time is None:
                self._sim_time = True
            if self._sim_time:
                self._sim_now = max(self._sim_now, sample.stamp_ns)
            else:
                sample.stamp_ns = None
        once = self._latched_recorded.get(topic)
        if once is None:
            once = self._latched_recorded[topic] = LatchedOnce()
        if not once.fresh(sample.latch):
            return ()  # a latched publication recorded already (it comes in several ways)
        if not self.options.wants(topic):
            return ()
        if sample.stamp_ns is None:  # from a publisher in wall time: stamped at receipt
            if self._sim_time is False:
                sample.stamp_ns = sample.wall_ns
            elif self._clock_ns is not None:
                sample.stamp_ns = self._clock_ns
        self._pending.append(sample)
        return self._release()

    def tick(self) -> Iterable[Sample]:
        if self._sim_time is None and self._pending:
            self._sim_time = self._ask_sim_time()
        return self._release()

    def now_ns(self) -> int | None:
        if self._sim_time is False:
            return time.time_ns()
        if self._clock_ns is None and not self._sim_now:
            return None
        return max(self._clock_ns or 0, self._sim_now)

    def _clock(self, data: bytes) -> None:
        try:
            clock = types().deserialize(data, "rosgraph_msgs/msg/Clock")
        except Exception:  # noqa: BLE001 (a peer sent something else)
            return
        self._clock_ns = clock.clock.sec * 1_000_000_000 + clock.clock.nanosec
        if self._sim_time is None:
            self._sim_time = True

    def _release(self) -> list[Sample]:
        """Pending samples whose type, latching and stamp are known now, in order (one that
        waits for its publisher's details holds back those after it)."""
        out = []
        pending = self._pending
        now = time.time_ns()
        while pending:
            sample = pending[0]
            topic = sample.topic
            full = self._types.get(topic)
            waited = (now - sample.wall_ns) / 1e9
            if full is None or topic not in self._latching:
                if waited < self.DETAILS_WAIT:
                    break
                if full is None:
                    pending.popleft()
                    logger.warning(
                        "not recording a message on %s: no publisher announced it", topic
                    )
                    continue
            if sample.stamp_ns is None:
                if self._clock_ns is not None and self._sim_time is not False:
                    sample.stamp_ns = self._clock_ns  # it came before the first /clock
                elif self._sim_time is False or (
                    self._sim_time is None and waited > self.WALL_WAIT
                ):
                    sample.stamp_ns = sample.wall_ns
                else:
                    break
            pending.popleft()
            sample.msgtype = full
            sample.latching = self._latching.get(topic, False)
            callers = self._callers.get(topic)
            sample.callerid = min(callers) if callers else None
            if topic not in self._announced:
                self._announced.add(topic)
                if not self.options.quiet:
                    logger.info("Subscribing to %s", topic)
            out.append(sample)
        return out

    def close(self) -> None:
        self._closed = True
        for tap in self._taps:
            tap.undeclare()
        self._taps.clear()
        if self._watch is not None:
            self._watch.undeclare()
            self._watch = None
