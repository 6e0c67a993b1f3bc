"""The executor's batches: a timer callback that moves simulated time on by itself (physics
running many steps at once) sees and changes nothing the others would notice."""

from __future__ import annotations

import itertools

import pytest

from belvedere.graph._executor import MAX_BATCH_NS, NS, Executor

MS = 1_000_000


def _trace(batched: bool, duration: float = 0.1) -> list[tuple[str, int]]:
    """A 1 ms 'physics' timer (batching up to 50 steps when asked) beside 7 ms and 10 ms
    timers; what fired at which time."""
    ex = Executor(sim_time=True)
    fired: list[tuple[str, int]] = []
    physics = ex.add_timer(0.001, lambda: None)

    def step() -> None:
        now = ex.now_ns()
        fired.append(("physics", now))
        if batched:
            last = min(ex.horizon_ns(), now + 49 * MS)
            for t in range(now + MS, last + 1, MS):
                ex.advance_to(t)
                fired.append(("physics", t))

    physics.callback = step
    ex.add_timer(0.007, lambda: fired.append(("a", ex.now_ns())))
    ex.add_timer(0.010, lambda: fired.append(("b", ex.now_ns())))
    ex.run(duration=duration, rtf=None)
    assert ex.now_ns() == round(duration * NS)
    return fired


def test_a_batching_callback_fires_as_if_stepped_one_by_one() -> None:
    one_by_one = _trace(batched=False)
    assert _trace(batched=True) == one_by_one
    assert one_by_one.count(("a", 7 * MS)) == 1
    # at equal times the other timer (older) fires first, in both
    assert one_by_one.index(("b", 10 * MS)) < one_by_one.index(("physics", 10 * MS))


def test_the_horizon() -> None:
    ex = Executor(sim_time=True)
    seen: list[int] = []
    ex.add_timer(0.001, lambda: seen.append(ex.horizon_ns()), oneshot=True)
    ex.add_timer(0.005, lambda: None)
    ex.run(duration=0.01, rtf=None)
    assert seen == [5 * MS - 1]  # just before the next timer

    ex = Executor(sim_time=True)
    ex.add_timer(0.001, lambda: seen.append(ex.horizon_ns()), oneshot=True)
    ex.run(duration=0.003, rtf=None)
    assert seen[-1] == 3 * MS  # no other timer: the run's end

    ex = Executor(sim_time=True)
    ex.add_timer(0.001, lambda: seen.append(ex.horizon_ns()), oneshot=True)
    ex.run(duration=10.0, rtf=1000.0)
    assert seen[-1] == MS + MAX_BATCH_NS  # never far: pacing, and outside changes

    ex = Executor(sim_time=True)

    def with_outside_event() -> None:
        ex.post(lambda: None)
        seen.append(ex.horizon_ns())

    ex.add_timer(0.001, with_outside_event, oneshot=True)
    ex.run(duration=0.003, rtf=None)
    assert seen[-1] == MS  # something from outside waits: no batch


def test_advancing_past_the_horizon_or_back_is_refused() -> None:
    ex = Executor(sim_time=True)
    errors: list[str] = []

    def bad() -> None:
        for target in (ex.now_ns() - 1, ex.horizon_ns() + 1):
            with pytest.raises(ValueError, match="cannot advance simulated time") as info:
                ex.advance_to(target)
            errors.append(str(info.value))

    ex.add_timer(0.001, bad, oneshot=True)
    ex.add_timer(0.002, lambda: None)
    ex.run(duration=0.003, rtf=None)
    assert len(errors) == 2


def test_wall_clock_graphs_do_not_batch() -> None:
    ex = Executor(sim_time=False)
    seen: list[tuple[int, int]] = []
    ex.add_timer(0.001, lambda: seen.append((ex.horizon_ns(), ex.now_ns())), oneshot=True)
    ex.run(duration=0.01, rtf=None)
    horizon, after = seen[0]
    assert horizon <= after  # the wall clock's now: nothing to run ahead of


def test_an_idle_timer_does_not_stop_a_batch() -> None:
    """A timer whose callback would do nothing (a /clock nobody listens to) lets a batch run
    past it and is not fired for it, its phase kept; one that finds work during a batch fires
    once, late, when the batch ends, and on time again after."""
    ex = Executor(sim_time=True)
    listening = [False]
    fired: list[int] = []
    clock = ex.add_timer(0.01, lambda: fired.append(ex.now_ns()))
    clock.idle = lambda: not listening[0]
    horizons: list[int] = []
    found = [False]

    def physics() -> None:
        horizon = ex.horizon_ns()
        horizons.append(horizon)
        if found[0]:  # as a subscriber appearing from another thread, after the planning
            listening[0] = True
        ex.advance_to(min(horizon, ex.now_ns() + 14 * MS))

    ex.add_timer(0.001, physics)
    ex.run(duration=0.05, rtf=None)
    assert horizons[0] == MS + MAX_BATCH_NS  # not stopped at the timer's 10 ms
    assert fired == []  # idle throughout: never fired
    assert clock.due_ns % (10 * MS) == 0  # still on its 10 ms grid
    found[0] = True
    start = ex.now_ns()
    ex.run(duration=0.05, rtf=None)
    assert fired[0] == start + 15 * MS  # late, once, when that batch ended
    on_time = fired[1:]
    assert len(on_time) >= 3
    assert {b - a for a, b in itertools.pairwise(on_time)} == {10 * MS}


def test_a_planned_batch_holds_when_something_arrives_meanwhile() -> None:
    """Another thread's message (or a /clock subscriber appearing) while physics steps a
    planned batch: the batch still ends where it was planned; the news waits for it."""
    ex = Executor(sim_time=True)
    ends: list[int] = []
    listening = [False]
    clock = ex.add_timer(0.01, lambda: None)
    clock.idle = lambda: not listening[0]

    def physics() -> None:
        planned = ex.horizon_ns()
        ex.post(lambda: None)  # arrives while the steps run
        listening[0] = True
        ex.advance_to(planned)
        ends.append(planned)

    ex.add_timer(0.001, physics, oneshot=True)
    ex.run(duration=0.05, rtf=None)
    assert ends == [MS + MAX_BATCH_NS]


def test_a_call_from_another_thread_runs_on_the_executor_thread() -> None:
    import threading

    ex = Executor(sim_time=True)
    ex.add_timer(0.001, lambda: None)
    with pytest.raises(TimeoutError, match=r"did not run the call within 0\.05 s"):
        ex.call(lambda: 1, timeout=0.05)  # nothing runs the executor yet
    runner = threading.Thread(target=ex.run, kwargs={"rtf": 1.0})
    runner.start()
    try:
        assert ex.call(lambda: threading.current_thread(), timeout=30.0) is runner

        def fail() -> None:
            msg = "raised on the executor thread"
            raise ValueError(msg)

        with pytest.raises(ValueError, match="raised on the executor thread"):
            ex.call(fail, timeout=30.0)
    finally:
        ex.stop()
        runner.join(timeout=30.0)
