"""rospy's time: ``Time``/``Duration``, the node's clock (wall or ``/clock``), sleeping,
``Rate`` and ``Timer``, with rospy's semantics."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import Any, Self

from belvedere.graph import NS
from belvedere.ros1._rostime import Duration as GenpyDuration
from belvedere.ros1._rostime import Time as GenpyTime
from belvedere.ros1.rospy import _state
from belvedere.ros1.rospy._exceptions import (
    ROSInitException,
    ROSInterruptException,
    ROSTimeMovedBackwardsException,
)

__all__ = [
    "Duration",
    "Rate",
    "Time",
    "Timer",
    "TimerEvent",
    "get_rostime",
    "get_time",
    "is_wallclock",
    "sleep",
]


class Duration(GenpyDuration):
    """rospy's ``Duration`` (genpy's, with rospy's ``repr``)."""

    __slots__ = ()
    _kind = "rospy.Duration"


class Time(GenpyTime):
    """rospy's ``Time``: genpy's, plus :meth:`now`."""

    __slots__ = ()
    _kind = "rospy.Time"

    @staticmethod
    def now() -> Time:
        return get_rostime()

    @classmethod
    def from_seconds(cls, float_secs: float) -> Self:
        return cls.from_sec(float_secs)


def get_rostime() -> Time:
    """The node's time: simulated (``/clock``) when ``/use_sim_time`` is set, else wall."""
    runtime = _state.current()
    if runtime is None:
        msg = "time is not initialized. Have you called init_node()?"
        raise ROSInitException(msg)
    ns = runtime.now_ns()
    return Time(ns // NS, ns % NS)


def get_time() -> float:
    return get_rostime().to_sec()


def is_wallclock() -> bool:
    runtime = _state.current()
    return runtime is None or not runtime.sim_time


def _seconds(duration: float | GenpyDuration) -> float:
    return duration.to_sec() if isinstance(duration, GenpyDuration) else float(duration)


def sleep(duration: float | GenpyDuration) -> None:
    """Sleep in the node's time. In wall time a negative duration returns at once; in
    simulated time the sleep follows ``/clock`` (waiting for its first message), and ends
    with ROSInterruptException on shutdown or ROSTimeMovedBackwardsException if the clock
    jumps back."""
    runtime = _state.current()
    stop = _state.shutdown_event()
    if runtime is None or not runtime.sim_time:
        seconds = _seconds(duration)
        if seconds > 0:
            stop.wait(seconds)  # rospy sleeps it out; waking at shutdown loses nothing
        return
    span = duration if isinstance(duration, GenpyDuration) else Duration.from_sec(duration)
    cond = runtime.clock
    with cond:
        while runtime.clock_ns == 0 and not stop.is_set():
            cond.wait(0.3)
        start = runtime.clock_ns
        target = start + span.to_nsec()
        while start <= runtime.clock_ns < target and not stop.is_set():
            cond.wait(0.5)
        now = runtime.clock_ns
    if now < start:
        raise ROSTimeMovedBackwardsException((start - now) / NS)
    if stop.is_set():
        msg = "ROS shutdown request"
        raise ROSInterruptException(msg)


class Rate:
    """Keep a loop at ``hz`` in the node's time."""

    def __init__(self, hz: float, reset: bool = False) -> None:
        self.last_time: GenpyTime = get_rostime()
        self.sleep_dur = Duration(0, int(1e9 / hz))
        self._reset = reset

    def _remaining(self, now: GenpyTime) -> GenpyDuration:
        if self.last_time > now:
            self.last_time = now
        elapsed: GenpyDuration = now - self.last_time
        return self.sleep_dur - elapsed

    def remaining(self) -> GenpyDuration:
        return self._remaining(get_rostime())

    def sleep(self) -> None:
        now = get_rostime()
        try:
            sleep(self._remaining(now))
        except ROSTimeMovedBackwardsException:
            if not self._reset:
                raise
            self.last_time = get_rostime()
            return
        self.last_time = self.last_time + self.sleep_dur
        # A loop slower than the rate (or a jump forward) starts counting again from now.
        if now - self.last_time > self.sleep_dur * 2:
            self.last_time = now


class TimerEvent:
    """What a ``Timer`` callback is told: expected and real times of this and the last call."""

    def __init__(
        self,
        last_expected: GenpyTime | None,
        last_real: GenpyTime | None,
        current_expected: GenpyTime,
        current_real: GenpyTime,
        last_duration: float | None,
    ) -> None:
        self.last_expected = last_expected
        self.last_real = last_real
        self.current_expected = current_expected
        self.current_real = current_real
        self.last_duration = last_duration


class Timer(threading.Thread):
    """Calls ``callback(TimerEvent)`` every ``period`` (a Duration) of the node's time, on a
    thread of its own, until shutdown or :meth:`shutdown`."""

    def __init__(
        self,
        period: GenpyDuration,
        callback: Callable[[TimerEvent], Any],
        oneshot: bool = False,
        reset: bool = False,
    ) -> None:
        super().__init__(daemon=True)
        self._period = period
        self._callback = callback
        self._oneshot = oneshot
        self._reset = reset
        self._shutdown = False
        self.start()

    def shutdown(self) -> None:
        self._shutdown = True

    def run(self) -> None:
        rate = Rate(1.0 / self._period.to_sec(), reset=self._reset)
        current_expected = get_rostime() + self._period
        last_expected: GenpyTime | None = None
        last_real: GenpyTime | None = None
        last_duration: float | None = None
        while not _state.is_shutdown() and not self._shutdown:
            try:
                rate.sleep()
            except ROSInterruptException:
                if _state.is_shutdown():
                    break
                current_expected = get_rostime() + self._period
                continue
            if self._shutdown:
                break
            current_real = get_rostime()
            started = time.time()
            self._callback(
                TimerEvent(last_expected, last_real, current_expected, current_real, last_duration)
            )
            if self._oneshot:
                break
            last_duration = time.time() - started
            last_expected, last_real = current_expected, current_real
            current_expected = current_expected + self._period
