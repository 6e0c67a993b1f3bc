"""Playing bags back: what ``rosbag play`` does, on a belvedere graph.

A :class:`Player` is a node's publishers and one timer: each message goes out when the
graph's time reaches its place in the bag, so in simulated time the same bag and graph
give the same run at any pace (``--rtf max`` too). With ``clock`` the graph's time *is* the
bag's: it starts at the bag's first message and the graph's clock announces it on
``/clock``, as ``rosbag play --clock``; otherwise the bag is laid on the graph's time from
when playing starts, ``rate`` times faster.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

from belvedere.bags._files import BagFile, merged_messages, open_bag
from belvedere.bags._model import BagError, BagMessage, Decoder, one_line
from belvedere.bags._options import PlayOptions
from belvedere.errors import BelvedereError
from belvedere.graph import NS, Node, Publisher, Timer
from belvedere.msgs import short, types

__all__ = ["PlayProgress", "Player"]

logger = logging.getLogger("belvedere.bags")

CLOCK = "/clock"


@dataclass(frozen=True, slots=True)
class PlayProgress:
    bag_ns: int
    """The bag time of the last message published."""
    done_s: float
    """Seconds of the bags played (from the start point)."""
    total_s: float
    paused: bool


class Player:
    """Publishes the messages of bags on ``node``'s graph, in time order."""

    def __init__(
        self,
        node: Node,
        options: PlayOptions,
        *,
        bags: list[BagFile] | None = None,
        on_progress: Callable[[PlayProgress], None] | None = None,
    ) -> None:
        self.node = node
        self.options = options
        self.on_progress = on_progress
        self.bags = bags if bags is not None else [open_bag(p) for p in options.bags]
        self.done = threading.Event()
        """Set when the last message is out (never with ``loop`` or ``keep_alive``)."""
        self.published = 0
        self._decoder = Decoder()
        self._pubs: dict[str, Publisher] = {}
        self._topics: set[str] = set()
        graph = node.graph
        self.clock = options.clock and graph.sim_time
        if options.clock and not graph.sim_time:
            logger.warning("--clock: this graph runs on the wall clock; /clock is not published")
        self._undecodable: dict[str, int] = {}
        """Messages skipped per topic because they could not be decoded (since last said)."""
        self.undecodable = 0
        """Messages skipped in all because they could not be decoded."""
        self._advertise()
        counted = [b for b in self.bags if sum(b.counts.values())]
        names = ", ".join(str(b.path) for b in self.bags)
        if not counted:
            hold = "holds" if len(self.bags) == 1 else "hold"
            damaged = any(b.skipped.places for b in self.bags)
            what = "readable messages (the warning above says why)" if damaged else "messages"
            msg = f"nothing to play: {names} {hold} no {what}"
            raise BagError(msg)
        if not self._topics:
            raise self._nothing_chosen(names)
        first = min(b.start_ns for b in counted)
        last = max(b.end_ns for b in counted)
        self.start_ns = first + round(options.start * NS)
        if self.start_ns > last:
            msg = (
                f"nothing to play: -s {options.start:g} starts after the last message, "
                f"{(last - first) / NS:.1f} s into {names}"
            )
            raise BagError(msg)
        self.stop_ns = (
            last if options.duration is None else self.start_ns + round(options.duration * NS)
        )
        self.total_s = max(0.0, (min(self.stop_ns, last) - self.start_ns) / NS)
        if self.clock:
            graph.executor.start_at(self.start_ns)
        self._paused = options.pause
        self._paused_at: int | None = None
        self._timer: Timer | None = None
        self._messages: Iterator[tuple[int, BagMessage]] | None = None
        self._next: BagMessage | None = None
        self._base_graph = 0
        self._base_bag = self.start_ns
        self._last_stamp: int | None = None
        self._started = False

    # --- set-up ---------------------------------------------------------------------------
    def _advertise(self) -> None:
        options = self.options
        decoder = self._decoder
        kinds: dict[str, str] = {}
        latched: dict[str, bool] = {}
        for bag in self.bags:
            for conn in bag.connections:
                if options.topics is not None and conn.topic not in options.topics:
                    continue
                if conn.topic == CLOCK and self.clock:
                    continue  # the graph announces the bag's time itself
                if not decoder.usable(conn, str(bag.path)):
                    continue
                known = kinds.setdefault(conn.topic, conn.msgtype)
                if known != conn.msgtype:
                    logger.warning(
                        "%s: %s is %s in one bag and %s in another; playing the first",
                        bag.path,
                        conn.topic,
                        short(known),
                        short(conn.msgtype),
                    )
                    continue
                latched[conn.topic] = latched.get(conn.topic, False) or conn.latching
        for topic, msgtype in sorted(kinds.items()):
            self._pubs[topic] = self.node.publisher(
                options.prefix + topic if options.prefix else topic,
                types().resolve(msgtype),
                latch=latched[topic],
                queue_size=100,
                seq_rule="given",
            )
        self._topics = set(kinds)
        if options.topics is not None:
            present = {c.topic for bag in self.bags for c in bag.connections}
            missing = sorted(options.topics - present)
            if missing and options.topics & present:
                logger.warning("--topics: no bag has %s; playing the others", ", ".join(missing))

    def _nothing_chosen(self, names: str) -> BagError:
        """Why no topic is played: none of --topics is in the bags, or no type is readable."""
        present = sorted({c.topic for bag in self.bags for c in bag.connections})
        chosen = self.options.topics
        if chosen is not None and not chosen & set(present):
            msg = f"nothing to play: {names} has no topic {', '.join(sorted(chosen))}"
            return BagError(msg, hint="its topics: " + ", ".join(present))
        msg = (
            f"nothing to play: belvedere cannot read the type of any topic chosen in {names} "
            "(the warnings above say why)"
        )
        return BagError(msg)

    @property
    def publishers(self) -> list[Publisher]:
        return list(self._pubs.values())

    def start(self) -> None:
        """Start playing from the graph's time now (call on the executor thread, or before
        the graph runs)."""
        if self._started:
            return
        self._started = True
        self._base_graph = self.node.now_ns()
        if self.clock:
            self._base_graph = self._base_bag = self.start_ns
        self._restart()
        if self._next is None:  # nothing in the time chosen, or nothing readable
            self._end()
            return
        if self._paused:
            self._report()
            if not self.clock:
                self._paused_at = self.node.now_ns()
                return
            self.node.graph.executor.pause(True)
        self._schedule()

    def _restart(self) -> None:
        self._messages = merged_messages(
            self.bags, topics=self._topics, start_ns=self.start_ns, stop_ns=self.stop_ns + 1
        )
        self._next = self._advance()

    def _advance(self) -> BagMessage | None:
        assert self._messages is not None
        try:
            for _, message in self._messages:
                conn = message.connection
                if conn.topic in self._pubs and self._decoder.usable(conn):
                    return message
        except BelvedereError as err:  # (the readers skip damaged chunks: a last resort)
            logger.warning("stopped reading: %s", err.message)
            self._messages = iter(())
        return None

    # --- timing ---------------------------------------------------------------------------
    def _target(self, stamp: int) -> int:
        options = self.options
        if options.immediate:
            return self._base_graph
        if self.clock:
            return self._base_graph + (stamp - self._base_bag)
        return self._base_graph + round((stamp - self._base_bag) / options.rate)

    def _schedule(self) -> None:
        message = self._next
        if message is None:
            return
        skip = self.options.skip_empty
        if skip is not None and self._last_stamp is not None:
            gap = message.stamp_ns - self._last_stamp
            if gap > skip * NS:
                self._base_bag += gap  # as if the empty stretch were not there
        delay = max(0, self._target(message.stamp_ns) - self.node.now_ns())
        if self._timer is not None:
            self._timer.cancel()
        self._timer = self.node.timer(delay / NS, self._fire, oneshot=True)

    def _fire(self) -> None:
        if self._paused and not self.clock:
            return  # (with the bag's clock, pausing stops the graph's time instead)
        now = self.node.now_ns()
        while self._next is not None and self._target(self._next.stamp_ns) <= now:
            message = self._next
            self._publish(message)
            self._next = self._advance()
            if message.connection.topic in self.options.pause_topics:
                self.pause(True)
                if not self.clock:
                    return
                break
        if self._next is None:
            self._end()
            return
        self._schedule()

    def _publish(self, message: BagMessage) -> None:
        try:
            msg = self._decoder.decode(message)
        except Exception as err:  # noqa: BLE001 (a damaged message: skip it, say so)
            topic = message.connection.topic
            self.undecodable += 1
            seen = self._undecodable[topic] = self._undecodable.get(topic, 0) + 1
            if seen == 1:
                logger.warning(
                    "skipping a message on %s at %.3f s: it cannot be decoded (%s)",
                    topic,
                    message.stamp_ns / NS,
                    one_line(err),
                )
            return
        self._pubs[message.connection.topic].publish(msg)
        self.published += 1
        self._last_stamp = message.stamp_ns
        self._report()

    def _end(self) -> None:
        if self.options.loop and self._last_stamp is not None:
            last = self._last_stamp
            self._base_graph = self._target(last)
            self._base_bag = self.start_ns
            self._last_stamp = None
            self._restart()
            self._schedule()
            return
        self._report()
        for topic, n in sorted(self._undecodable.items()):
            if n > 1:
                logger.warning("skipped %d messages on %s that could not be decoded", n, topic)
        self._undecodable.clear()
        if not self.options.keep_alive:
            self.done.set()

    def _report(self) -> None:
        if self.on_progress is None:
            return
        stamp = self._last_stamp if self._last_stamp is not None else self.start_ns
        self.on_progress(
            PlayProgress(
                stamp,
                min(self.total_s, max(0.0, (stamp - self.start_ns) / NS)),
                self.total_s,
                self._paused,
            )
        )

    # --- pausing (executor thread; see the post_* variants for other threads) -------------
    @property
    def paused(self) -> bool:
        return self._paused

    def pause(self, paused: bool) -> None:
        if paused == self._paused or not self._started:
            self._paused = paused
            return
        self._paused = paused
        executor = self.node.graph.executor
        if self.clock:
            executor.pause(paused)
        elif paused:
            self._paused_at = self.node.now_ns()
        else:
            if self._paused_at is not None:
                self._base_graph += self.node.now_ns() - self._paused_at
            self._paused_at = None
            self._schedule()
        self._report()

    def step(self) -> None:
        """While paused, publish the next message (and everything at its time)."""
        if not self._paused or self._next is None:
            return
        stamp = self._next.stamp_ns
        if self.clock:  # time moves on to the message, whose timer then fires
            self.node.graph.executor.step(max(0, self._target(stamp) - self.node.now_ns()) / NS)
            return
        while self._next is not None and self._next.stamp_ns == stamp:
            self._publish(self._next)
            self._next = self._advance()
        if self._paused_at is not None:
            self._base_graph += self.node.now_ns() - self._target(stamp)
            self._paused_at = self.node.now_ns()
        if self._next is None:
            self._end()

    def post(self, action: Callable[[], Any]) -> None:
        """Run ``action`` (:meth:`pause`, :meth:`step`…) on the graph's executor thread."""
        self.node.graph.executor.post(action)

    @property
    def skipped(self) -> bool:
        """Whether anything was skipped as damaged (a chunk, or a message)."""
        return self.undecodable > 0 or any(b.skipped.places for b in self.bags)

    def close(self) -> None:
        for bag in self.bags:
            bag.close()
