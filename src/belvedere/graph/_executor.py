"""The executor: one thread runs every callback, timer and simulation step, in a defined order.

Time is simulated (advanced by the executor from one timer to the next) or the wall clock.
In simulated time the order is fixed: timers fire by due time, then by creation; messages are
delivered after the callback that published them, first published first delivered. The same
inputs and seed give the same outputs. With ``rtf=None`` simulated time runs as fast as the
CPU allows; with a number it is paced to that multiple of the wall clock.
"""

from __future__ import annotations

import heapq
import queue
import random
import threading
import time
from collections import deque
from collections.abc import Callable
from typing import Final, Protocol, TypeVar

__all__ = ["Executor", "Timer"]

T = TypeVar("T")

NS: Final = 1_000_000_000

MAX_BATCH_NS: Final = 20_000_000
"""The most simulated time one callback may run ahead (advance_to): pacing to the wall clock
stays smooth to 20 ms, and what changes outside simulated time (a subscriber appearing in
another process) is seen within 20 ms."""


class _Deliverable(Protocol):
    def deliver_one(self) -> bool:
        """Run one pending callback; True if more are pending."""
        ...


class Timer:
    """A periodic (or one-shot) callback; cancel with :meth:`cancel`."""

    __slots__ = ("_cancelled", "callback", "due_ns", "idle", "oneshot", "period_ns")

    def __init__(
        self, period_ns: int, callback: Callable[[], object], due_ns: int, oneshot: bool
    ) -> None:
        self.period_ns = period_ns
        self.callback = callback
        self.due_ns = due_ns
        self.oneshot = oneshot
        self._cancelled = False
        self.idle: Callable[[], bool] | None = None
        """Whether the callback would do nothing now (a publisher nobody listens to): a batch
        may then run past the timer, which fires late, once, when the batch ends."""

    def cancel(self) -> None:
        self._cancelled = True

    @property
    def cancelled(self) -> bool:
        return self._cancelled


class Executor:
    """Runs the graph's callbacks on one thread."""

    def __init__(self, *, sim_time: bool = True, start_ns: int = 0, seed: int = 0) -> None:
        self.sim_time = sim_time
        self._sim_ns = start_ns
        self._timers: list[tuple[int, int, Timer]] = []
        self._seq = 0
        self._ready: deque[_Deliverable] = deque()
        self._inbox: queue.SimpleQueue[Callable[[], object]] = queue.SimpleQueue()
        self._stop = threading.Event()
        self.random = random.Random(seed)
        """The graph's seeded randomness (noise models, randomized buttons…)."""
        self.thread: threading.Thread | None = None
        self.rtf: float | None = None
        self.paused = False
        self._step_to: int | None = None
        self._pace_wall = time.monotonic()
        self._pace_sim = start_ns
        self._end_ns: int | None = None
        self._following = False
        self._clock_seen = False

    # --- time ----------------------------------------------------------------------------------
    def now_ns(self) -> int:
        return self._sim_ns if self.sim_time else time.time_ns()

    def follow(self) -> None:
        """Take simulated time from outside (another process's ``/clock``, fed to
        :meth:`set_clock`) instead of advancing it: timers fire as that clock passes them."""
        self._following = True

    @property
    def following(self) -> bool:
        return self._following

    def set_clock(self, ns: int) -> None:
        """The outside clock reads ``ns`` (executor thread; time never goes back)."""
        self._sim_ns = max(self._sim_ns, ns)
        self._clock_seen = True

    def start_at(self, ns: int) -> None:
        """Begin simulated time at ``ns`` rather than where it stands (a recording's start,
        for a bag played in its own time): every timer keeps its phase. Only before the
        executor first runs."""
        if not self.sim_time or self.thread is not None:
            msg = "only a simulated clock that has not run yet can be set"
            raise ValueError(msg)
        delta = ns - self._sim_ns
        self._sim_ns = self._pace_sim = ns
        for _, _, timer in self._timers:
            timer.due_ns += delta
        self._timers = [(due + delta, seq, timer) for due, seq, timer in self._timers]
        heapq.heapify(self._timers)

    # --- registration ----------------------------------------------------------------------------
    def add_timer(
        self, period_s: float, callback: Callable[[], object], *, oneshot: bool = False
    ) -> Timer:
        period_ns = round(period_s * NS)
        if period_ns <= 0 and not oneshot:
            msg = f"timer period must be positive, got {period_s!r} s"
            raise ValueError(msg)
        timer = Timer(period_ns, callback, self.now_ns() + max(period_ns, 0), oneshot)
        self._push(timer)
        return timer

    def _push(self, timer: Timer) -> None:
        self._seq += 1
        heapq.heappush(self._timers, (timer.due_ns, self._seq, timer))

    def ready(self, item: _Deliverable) -> None:
        """``item`` has a pending callback (called from the executor thread)."""
        self._ready.append(item)

    def has_ready(self) -> bool:
        """Whether a delivery is pending (a message published and not yet handed over)."""
        return bool(self._ready)

    def post(self, fn: Callable[[], object]) -> None:
        """Run ``fn`` on the executor thread (safe from any thread)."""
        self._inbox.put(fn)

    def call(self, fn: Callable[[], T], timeout: float) -> T:
        """``fn()`` run on the executor thread between callbacks (here, when this is that
        thread), its result returned and its error raised here. A barrier too: what was
        posted before it has run when it returns. TimeoutError when not done in ``timeout``."""
        if self.thread is threading.current_thread():
            return fn()
        done = threading.Event()
        result: list[T] = []
        failure: list[BaseException] = []

        def run() -> None:
            try:
                result.append(fn())
            except BaseException as err:  # noqa: BLE001 (raised again on the caller's thread)
                failure.append(err)
            finally:
                done.set()

        self.post(run)
        if not done.wait(timeout):
            msg = f"the executor did not run the call within {timeout:g} s"
            raise TimeoutError(msg)
        if failure:
            raise failure[0]
        return result[0]

    def stop(self) -> None:
        self._stop.set()
        self._inbox.put(lambda: None)  # wake a waiting loop

    @property
    def stopped(self) -> bool:
        return self._stop.is_set()

    # --- running ---------------------------------------------------------------------------------
    def run_ready(self) -> None:
        """Run every pending delivery (executor thread only)."""
        ready = self._ready
        while ready:
            item = ready.popleft()
            if item.deliver_one():
                ready.append(item)

    def _drain(self) -> None:
        # Deliver after each outside event, so a burst from another process does not pile up
        # beyond the subscribers' queue sizes before anyone runs.
        inbox = self._inbox
        while True:
            self.run_ready()
            if inbox.empty():  # (this thread alone takes from it: not empty stays so)
                break
            inbox.get_nowait()()

    def _fire_due(self, now_ns: int) -> None:
        timers = self._timers
        while timers and timers[0][0] <= now_ns:
            _, _, timer = heapq.heappop(timers)
            if timer.cancelled:
                continue
            timer.callback()
            if not timer.oneshot and not timer.cancelled:
                # A callback that advanced the clock is next due a period after where it got to.
                timer.due_ns = max(timer.due_ns, self._sim_ns) + timer.period_ns
                self._push(timer)
            self._drain()

    def horizon_ns(self) -> int:
        """The latest simulated time the timer callback running now may move the clock to with
        :meth:`advance_to` without passing anything else: just before the next other timer is
        due (at equal times the other one fires first, as it would have), no further than the
        end of the run or of a step or :data:`MAX_BATCH_NS`, and nowhere while outside events
        are waiting. Wall-clock graphs cannot run ahead."""
        if not self.sim_time or self._following:
            return self.now_ns()
        if not self._inbox.empty() or self._ready:
            return self._sim_ns
        return self._limit_ns(planning=True)

    def _limit_ns(self, *, planning: bool) -> int:
        """How far simulated time may run ahead. Planning, an idle timer does not count; once
        a batch is taken, no timer that may be idle does (it may have found work since, from
        another thread: it then fires late, once), nor anything that arrived from outside."""
        now = self._sim_ns
        if self._following:
            return now  # the outside clock leads
        limit = now + MAX_BATCH_NS
        for due, _, timer in self._timers:
            if due - 1 >= limit or (timer.idle is not None and (not planning or timer.idle())):
                continue
            limit = due - 1
        for bound in (self._end_ns, self._step_to):
            if bound is not None:
                limit = min(limit, bound)
        return max(now, limit)

    def advance_to(self, ns: int) -> None:
        """Move simulated time on to ``ns`` from inside a timer callback (a batch of physics
        steps planned with :meth:`horizon_ns`), never back, never past another timer."""
        limit = self._limit_ns(planning=False)
        if not self.sim_time or ns < self._sim_ns or ns > limit:
            msg = f"cannot advance simulated time to {ns} ns (now {self._sim_ns}, limit {limit})"
            raise ValueError(msg)
        self._sim_ns = ns
        self._skip_idle(ns)

    def _skip_idle(self, ns: int) -> None:
        """Timers the batch ran past that are idle still: next due a whole number of periods
        on (their phase kept), as they would have done nothing (an idle ``/clock`` costs no
        firing a batch). One that found work meanwhile fires late, once."""
        timers = self._timers
        if not timers or timers[0][0] > ns:
            return
        late: list[tuple[int, int, Timer]] = []
        while timers and timers[0][0] <= ns:
            due, _, timer = timers[0]
            if timer.cancelled:
                heapq.heappop(timers)
            elif not timer.oneshot and timer.idle is not None and timer.idle():
                timer.due_ns = due + (1 + (ns - due) // timer.period_ns) * timer.period_ns
                self._seq += 1
                heapq.heapreplace(timers, (timer.due_ns, self._seq, timer))
            else:
                late.append(heapq.heappop(timers))
        for entry in late:
            heapq.heappush(timers, entry)

    def spin_once(self) -> None:
        """Deliver what is pending and fire timers that are due now (no time passes)."""
        self._drain()
        self._fire_due(self.now_ns())

    def run(
        self,
        *,
        duration: float | None = None,
        rtf: float | None = None,
        until: Callable[[], bool] | None = None,
    ) -> None:
        """Run until stopped, ``duration`` seconds of graph time pass, or ``until()`` holds.

        In simulated time ``rtf=None`` runs as fast as possible; otherwise time is paced to
        ``rtf`` times the wall clock (changeable while running with :meth:`set_rtf`; time
        stands still while paused (:meth:`pause`), except for :meth:`step`). In wall time, timers
        fire when they are due.
        """
        self.thread = threading.current_thread()
        self._stop.clear()
        self.rtf = rtf
        self._rebase()
        # Following a clock, the run's duration counts from the first time it reads.
        wait_for_clock = self._following and not self._clock_seen and duration is not None
        end_ns = None if duration is None else self.now_ns() + round(duration * NS)
        self._end_ns = end_ns
        while not self._stop.is_set():
            self._drain()
            if until is not None and until():
                return
            if wait_for_clock and self._clock_seen and duration is not None:
                wait_for_clock = False
                end_ns = self._end_ns = self._sim_ns + round(duration * NS)
            next_due = self._timers[0][0] if self._timers else None
            if end_ns is not None and (next_due is None or next_due > end_ns):
                next_due = end_ns
            if self.sim_time and self._following:
                if next_due is None or next_due > self._sim_ns:
                    self._wait(None)  # time moves only when the outside clock says so
                    continue
            elif self.sim_time:
                paced = self.rtf is not None
                if self.paused:
                    if self._step_to is None:
                        self._wait(None)  # paused: only outside events (or a step) come
                        continue
                    if next_due is None or next_due > self._step_to:
                        next_due = self._step_to
                    paced = False
                if next_due is None:
                    self._wait(None)  # nothing scheduled: only outside events can come
                    continue
                if paced and self.rtf is not None:
                    wall_due = self._pace_wall + (next_due - self._pace_sim) / NS / self.rtf
                    if self._wait_until(wall_due):
                        continue  # something arrived first: handle it, then re-plan
                self._sim_ns = max(self._sim_ns, next_due)
                if self._step_to is not None and self._sim_ns >= self._step_to:
                    self._step_to = None
                    self._rebase()
            else:
                if next_due is None:
                    self._wait(None)
                    continue
                if self._wait_until(time.monotonic() + (next_due - time.time_ns()) / NS):
                    continue
            if end_ns is not None and self.now_ns() >= end_ns:
                self._fire_due(end_ns)
                self._drain()
                return
            self._fire_due(self.now_ns())

    # --- pacing (safe from any thread) -----------------------------------------------------------
    def set_rtf(self, rtf: float | None) -> None:
        """Pace simulated time to ``rtf`` times the wall clock (None: as fast as possible)."""

        def apply() -> None:
            self.rtf = rtf
            self._rebase()

        self.post(apply)

    def pause(self, paused: bool) -> None:
        """Stop (or restart) simulated time; messages are still delivered while paused."""

        def apply() -> None:
            self.paused = paused
            self._step_to = None
            self._rebase()

        self.post(apply)

    def step(self, seconds: float) -> None:
        """While paused, advance simulated time by ``seconds`` (as fast as possible)."""

        def apply() -> None:
            if self.paused:
                self._step_to = self._sim_ns + round(seconds * NS)

        self.post(apply)

    def _rebase(self) -> None:
        self._pace_wall = time.monotonic()
        self._pace_sim = self._sim_ns

    def _wait_until(self, wall_deadline: float) -> bool:
        """Sleep until ``wall_deadline`` (monotonic); True if woken early by the inbox."""
        delay = wall_deadline - time.monotonic()
        if delay <= 0:
            return False
        return self._wait(delay)

    def _wait(self, timeout: float | None) -> bool:
        try:
            fn = self._inbox.get(timeout=timeout)
        except queue.Empty:
            return False
        fn()
        return True
