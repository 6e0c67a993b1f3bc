"""rostest's stock test nodes, run on the graph in its (simulated) time: ``hztest`` (a topic's
rate), ``paramtest`` (a parameter is set, perhaps to a value) and ``publishtest`` (topics are
published, or not, within a timeout), with the parameters, checks and failure messages of
ros_comm 1.15's nodes.

Each writes its one test case to the results file rostest gave it
(``--gtest_output=xml:FILE``) as rosunit writes it, and ends: status 0 when it passed, 1 when
not, as ``rostest.rosrun`` exits. Every wait (``wait_time``, ``test_duration``, a topic's
``timeout``) counts the graph's seconds: in a simulation, simulated ones, so a test takes the
same simulated time however fast the run goes.
"""

from __future__ import annotations

import shlex
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from belvedere.errors import BelvedereError
from belvedere.graph import Node
from belvedere.nodes._registry import NodeSpec, Session, Starter, end_node
from belvedere.ros1._junit import CaseResult, SuiteResult, write_results
from belvedere.ros1.rosunit import XML_OUTPUT_FLAG

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE"]

PACKAGE = "rostest"
POLL_S = 0.05
"""How often (graph time) a test looks at what it waits for."""
TYPE_POLL_S = 0.5
"""How often (graph time) a test asks the graph for the type of a topic not yet seen."""


class _Failed(Exception):  # noqa: N818 (unittest's failure, not an error)
    """A check that failed: its message is the test case's failure."""


@dataclass
class _Test:
    """One stock test node running: its case, where its result goes, how it ends."""

    session: Session
    node: Node
    classname: str
    case_name: str
    results_file: Path | None
    started: float = 0.0
    output: list[str] = field(default_factory=list)

    def say(self, text: str) -> None:
        self.output.append(text)
        self.node.logger.info("%s", text)

    def finish(self, failure: str | None, *, error: bool = False) -> None:
        if self.node.closed:
            return
        case = CaseResult(self.case_name, f"__main__.{self.classname}")
        case.time = max(0.0, self.node.now() - self.started)
        if failure is not None:
            (case.errors if error else case.failures).append(
                ("KeyError" if error else "AssertionError", failure)
            )
            self.node.logger.error("%s: %s", self.case_name, failure)
        suite = SuiteResult(
            "unittest.suite.TestSuite",
            tests=1,
            failures=int(failure is not None and not error),
            errors=int(failure is not None and error),
            time=case.time,
            cases=[case],
            system_out="\n".join(self.output) + "\n",
        )
        status = 0 if failure is None else 1
        if self.results_file is not None:
            try:
                write_results(self.results_file, suite)
            except BelvedereError as err:
                self.node.logger.error("%s", err.message)
                status = 1
        end_node(self.session, self.node, status)

    def guard(self, check: Callable[[], None]) -> Callable[[], None]:
        """``check`` as a timer's callback: a failed check ends the test."""

        def run() -> None:
            if self.node.closed:
                return
            try:
                check()
            except _Failed as failed:
                self.finish(str(failed))

        return run


def _results_file(spec: NodeSpec) -> Path | None:
    try:
        words = shlex.split(spec.args)
    except ValueError:
        words = spec.args.split()
    for word in words:
        if word.startswith(XML_OUTPUT_FLAG):
            return Path(word[len(XML_OUTPUT_FLAG) :])
    return None


def _true(condition: bool, message: str) -> None:
    """unittest's ``assert_``: its text is unittest's."""
    if not condition:
        msg = f"False is not true : {message}"
        raise _Failed(msg)


def _topic_type(node: Node, topic: str) -> str | None:
    """The type of ``topic`` if someone publishes it: a node here, or another process's."""
    found = node.graph.topics.get(topic)
    if found is not None and found.publishers:
        return found.type
    transport = node.graph.transport
    users = getattr(transport, "topic_users", None)
    if users is None:
        return None
    types = sorted(typ for kind, typ, _ in users(topic, timeout=0.5) if kind == "pub")
    return types[0] if types else None


def _when_published(node: Node, topic: str, callback: Callable[[Any], None]) -> Callable[[], None]:
    """rospy's ``Subscriber(topic, AnyMsg, …)``: subscribe once a publisher shows its type;
    call the returned function every poll until then."""
    subscribed = [False]
    next_ask = [0.0]

    def look() -> None:
        if subscribed[0] or node.now() < next_ask[0]:
            return
        next_ask[0] = node.now() + TYPE_POLL_S
        msg_type = _topic_type(node, topic)
        if msg_type is not None:
            node.subscribe(topic, msg_type, callback, queue_size=100)
            subscribed[0] = True

    return look


def _param(node: Node, name: str, default: Any = ...) -> Any:
    value = node.get_param(name, default)
    if value is ...:
        raise KeyError(name)
    return value


# --- hztest ------------------------------------------------------------------------------------
def _start_hztest(session: Session, spec: NodeSpec, node: Node) -> None:
    test = _Test(session, node, "HzTest", "test_hz", _results_file(spec), node.now())
    try:
        hz = float(_param(node, "~hz"))
        duration = float(_param(node, "~test_duration"))
        topic = node.resolve(str(_param(node, "~topic")))
        wait_time = float(_param(node, "~wait_time", 20.0))
        hzerror = float(_param(node, "~hzerror")) if hz != 0.0 else 0.0
        check_intervals = bool(_param(node, "~check_intervals", False))
    except KeyError as err:
        resolved = node.resolve(str(err.args[0]))
        test.finish(f"hztest not initialized properly. Parameter [{resolved}] not set.")
        return
    except (TypeError, ValueError) as err:
        test.finish(f"hztest: a parameter is not a number: {err}")
        return
    test.say(f"Hz: {hz}\nHz Error: {hzerror}\nTopic: {topic}\nTest Duration: {duration}")
    try:
        _true(hz >= 0.0, "bad parameter (hz)")
        _true(hzerror >= 0.0, "bad parameter (hzerror)")
        _true(duration > 0.0, "bad parameter (test_duration)")
    except _Failed as failed:
        test.finish(str(failed))
        return
    min_rate, max_rate = (hz - hzerror, hz + hzerror) if hz else (0.0, 0.0)
    min_interval = 1.0 / max_rate if hz else 0.0
    max_interval = 1.0 / min_rate if hz and min_rate > 0.0 else 0.0
    seen: list[float] = []
    errors: list[str] = []
    measuring_until: list[float] = []

    def received(_: Any) -> None:
        now = node.now()
        if check_intervals and seen:
            interval = now - seen[-1]
            if interval < min_interval:
                errors.append(
                    f"min_interval exceeded: {interval} [actual] vs. {min_interval} [min]"
                )
            elif max_interval > 0.0 and interval > max_interval:
                errors.append(
                    f"max_interval exceeded: {interval} [actual] vs. {max_interval} [max]"
                )
        seen.append(now)

    look = _when_published(node, topic, received)
    test.say("Waiting for messages")
    wait_until = node.now() + wait_time

    def check() -> None:
        look()
        now = node.now()
        if not measuring_until:
            if seen or now >= wait_until:
                if hz > 0.0:
                    _true(bool(seen), "no messages before timeout")
                elif seen:
                    msg = "True is not false : message received"
                    raise _Failed(msg)
                test.say("Starting rate measurement")
                measuring_until.append(now + duration)
            return
        if now < measuring_until[0]:
            return
        test.say("Done waiting, validating results")
        if hz > 0.0:
            _true(bool(seen), "no messages received")
        elif seen:
            msg = f"0 != {len(seen)}"
            raise _Failed(msg)
        _true(not errors, "\n".join(errors))
        if hz > 0.0:
            dt = seen[-1] - seen[0]
            _true(dt > 0.0, "only one message received")
            rate = (len(seen) - 1) / dt
            _true(
                rate >= min_rate,
                f"average rate ({rate:.3f}Hz) exceeded minimum ({min_rate:.3f}Hz)",
            )
            _true(
                rate <= max_rate,
                f"average rate ({rate:.3f}Hz) exceeded maximum ({max_rate:.3f}Hz)",
            )
            test.say(f"average rate {rate:.3f}Hz over {len(seen)} messages")
        test.finish(None)

    node.timer(POLL_S, test.guard(check))


# --- paramtest ---------------------------------------------------------------------------------
def _start_paramtest(session: Session, spec: NodeSpec, node: Node) -> None:
    test = _Test(session, node, "ParamTest", "test_param", _results_file(spec), node.now())
    try:
        target = str(_param(node, "~param_name_target"))
        expected = _param(node, "~param_value_expected", None)
        duration = float(_param(node, "~test_duration", 5.0))
        wait_time = float(_param(node, "~wait_time", 20.0))
    except KeyError as err:
        resolved = node.resolve(str(err.args[0]))
        test.finish(f"ParamTest not initialized properly. Parameter [{resolved}] not set.")
        return
    except (TypeError, ValueError) as err:
        test.finish(f"paramtest: a parameter is not a number: {err}")
        return
    test.say(f"Parameter: {target} Test Duration: {duration}")
    try:
        _true(duration > 0.0, "bad parameter (test_duration)")
        _true(bool(target), "bad parameter (testattr_paramname_target)")
    except _Failed as failed:
        test.finish(str(failed))
        return
    test.say("Waiting for parameters")
    wait_until = node.now() + wait_time

    def check() -> None:
        value = node.get_param(target, None)
        if value is None and node.now() < wait_until:
            return
        if expected:  # paramtest compares only a non-empty expectation, as ROS's does
            if expected != value:
                msg = f"{expected!r} != {value!r}"
                raise _Failed(msg)
        elif value is None:
            msg = "unexpectedly None"
            raise _Failed(msg)
        test.finish(None)

    node.timer(POLL_S, test.guard(check))


# --- publishtest -------------------------------------------------------------------------------
@dataclass
class _Checker:
    name: str
    deadline: float
    negative: bool
    received: bool = False

    def verdict(self, now: float) -> bool | None:
        """True: as wanted; False: not; None: not known yet (publishtest's
        ``assert_published``)."""
        if self.received:
            return not self.negative
        if now > self.deadline:
            return self.negative
        return None


def _start_publishtest(session: Session, spec: NodeSpec, node: Node) -> None:
    test = _Test(session, node, "PublishTest", "test_publish", _results_file(spec), node.now())
    wanted = node.get_param("~topics", [])
    topics: list[dict[str, Any]] = []
    for entry in wanted if isinstance(wanted, list) else []:
        if not isinstance(entry, dict) or "name" not in entry:
            test.finish("'name' field in rosparam is required but not specified.")
            return
        topics.append({"timeout": 10, "negative": False, **entry})
    if not topics:
        test.finish("No topic is specified in rosparam.")
        return
    checkers: list[_Checker] = []
    looks: list[Callable[[], None]] = []
    for topic in topics:
        name = node.resolve(str(topic["name"]))
        try:
            timeout = float(topic["timeout"])
        except (TypeError, ValueError):
            test.finish(f"publishtest: the timeout of {name} is not a number: {topic['timeout']!r}")
            return
        negative = bool(topic["negative"])
        test.say(f"Waiting [{name}] for [{timeout:g}] seconds with negative [{negative}]")
        checker = _Checker(name, node.now() + timeout, negative)
        checkers.append(checker)

        def received(_: Any, checker: _Checker = checker) -> None:
            checker.received = True

        looks.append(_when_published(node, name, received))
    finished: set[str] = set()

    def check() -> None:
        for look in looks:
            look()
        now = node.now()
        for checker in checkers:
            if checker.name in finished:
                continue
            verdict = checker.verdict(now)
            if verdict is None:
                continue
            finished.add(checker.name)
            if not verdict:
                state = "is published" if checker.negative else "is not published"
                msg = f"Topic [{checker.name}] {state}"
                raise _Failed(msg)
        if len(finished) == len(checkers):
            test.finish(None)

    node.timer(POLL_S, test.guard(check))


EXECUTABLES: dict[str, Starter] = {
    "hztest": _start_hztest,
    "paramtest": _start_paramtest,
    "publishtest": _start_publishtest,
}
JOINING = frozenset(EXECUTABLES)
"""Test nodes are clients: ``belvedere run rostest hztest`` joins the running graph."""
