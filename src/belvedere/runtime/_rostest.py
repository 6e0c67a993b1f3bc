"""rostest: one ``.test`` (or ``.launch``) file's ``<test>`` nodes run as ROS 1's rostest runs
them (ros_comm's ``rostest/runner.py``).

For each test, in the order unittest gives rostest's generated methods (by ``test-name``):
the launch's nodes are brought up on a graph of their own, in simulated time; the test node
starts once they are up, with ``--gtest_output=xml:DIR/PKG/rosunit-NAME.xml``, and runs to
its end or to its ``time-limit`` (wall-clock seconds, 60 by default); everything is torn down.
Its results file decides: failures or errors in it fail the test (and the run exits 2), no
file is a test that failed to run (exit 1), as a time-limit reached is (an error). A test
with ``retry="N"`` that failed runs again, up to N more times. The run's own JUnit file is
``DIR/PKG/rostest-FILE.xml`` (one case per test: did it run), and its summary is rosunit's.
"""

from __future__ import annotations

import logging
import os
import shlex
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

from belvedere import nodes
from belvedere.errors import BelvedereError
from belvedere.graph import Graph
from belvedere.launch import LaunchConfig, LaunchError, LaunchNode, load_launch
from belvedere.launch._runtime import LaunchRuntime, find_script
from belvedere.packages import PackageIndex, find_package_root, read_package_name
from belvedere.ros1._junit import (
    CaseResult,
    SuiteResult,
    read_results,
    summary_text,
    write_results,
)
from belvedere.ros1.rosunit import XML_OUTPUT_FLAG, xml_results_file
from belvedere.runtime._clock import hold_time_base, open_clock_transport
from belvedere.runtime._join import GraphAddress

__all__ = ["RostestOptions", "RostestOutcome", "rostest_name", "run_rostest"]

logger = logging.getLogger("belvedere.rostest")

POLL_S = 0.05
"""How often (wall clock) the test's process is looked at."""
RUNNER_CLASS = "rostest.runner.RosTest"


@dataclass(frozen=True)
class RostestOptions:
    """How ``belvedere test`` runs a file: plain values, so a worker process can take them."""

    address: GraphAddress = field(default_factory=GraphAddress)
    """The graph each test's launch makes (a free port of its own by default)."""
    results: Path | None = None
    """Where results go (``--results``); None: ROS's test results folder."""
    text: bool = False
    """rostest's ``--text``: the test nodes print unittest's report, no results files."""
    rtf: float | None = None
    """The simulation's real-time factor; None: as fast as the CPU allows."""
    seed: int = 0


@dataclass
class RostestOutcome:
    """What running one file gave: its summary, exit status and results file."""

    file: str
    package: str
    status: int
    """0: every test passed; 1: a test failed to run (or timed out); 2: a test failed."""
    summary: str
    results_file: str | None
    tests: int = 0
    failures: int = 0
    errors: int = 0


@dataclass
class _Runner:
    """The run's own unittest view: one case per ``<test>`` (did it run), and the tests'
    accumulated results."""

    cases: list[CaseResult] = field(default_factory=list)
    results: SuiteResult = field(default_factory=lambda: SuiteResult("rostest"))
    log: list[str] = field(default_factory=list)

    def say(self, text: str, *, error: bool = False) -> None:
        line = f"[ROSTEST]{text}"
        self.log.append(line)
        (logger.error if error else logger.info)("%s", line)


def rostest_name(package_dir: Path, test_file: Path) -> str:
    """rosunit's name of a test file's results: its path in the package, ``/`` as ``_``,
    without its extension (``test/demo.test`` → ``test_demo``)."""
    path = test_file.resolve()
    root = package_dir.resolve()
    relative = str(path.relative_to(root)) if path.is_relative_to(root) else str(test_file)
    name = relative.replace(os.sep, "_")
    return name.rpartition(".")[0] if "." in name else name


def run_rostest(
    path: Path,
    packages: PackageIndex,
    options: RostestOptions,
    *,
    args: dict[str, str] | None = None,
) -> RostestOutcome:
    """Run every ``<test>`` of ``path`` (with launch ``args``); its outcome.

    Raises:
        BelvedereError: the file cannot be read (a malformed file, a missing arg …), at its
            line, before anything runs.
    """
    root = find_package_root(path.resolve())
    package = read_package_name(root / "package.xml") if root is not None else "belvedere"
    config = load_launch(path, args=args, packages=packages, tests=True)
    for warning in config.warnings:
        logger.warning("%s", warning)
    for test in config.tests:
        _check_args(test)
    env = {} if options.results is None else {"ROS_TEST_RESULTS_DIR": str(options.results)}
    outname = rostest_name(root or path.parent, path)
    runner = _Runner()
    seen: set[str] = set()
    for test in sorted(config.tests, key=lambda t: f"test{t.test_name}"):
        name = str(test.test_name)
        case = CaseResult(f"test{name}", RUNNER_CLASS)
        runner.cases.append(case)
        started = time.monotonic()
        if name in seen:
            case.failures.append(
                ("AssertionError", f"Duplicate tests named [{name}] in rostest suite")
            )
            continue
        seen.add(name)
        missing = _missing(test, packages)
        if missing is not None:
            runner.say(missing, error=True)
            case.failures.append(("AssertionError", missing))
            continue
        _run_with_retries(config, test, package, packages, options, env, runner, case)
        case.time = time.monotonic() - started
    return _finish(path, package, outname, options, env, runner)


def _check_args(test: LaunchNode) -> None:
    """A test's ``args`` split as a shell splits them (the results file is added to them),
    or one error at its line before anything runs."""
    try:
        shlex.split(test.args)
    except ValueError as err:
        msg = f"<test> {test.test_name}: args={test.args!r} cannot be split: {err}"
        raise LaunchError(msg, test.source) from None


def _missing(test: LaunchNode, packages: PackageIndex) -> str | None:
    """rostest's message for a test node that cannot run (found before anything starts),
    with the line that asked for it."""
    where = f"{test.source}: " if test.source is not None else ""
    if nodes.find(test.pkg, test.type) is not None:
        return None
    try:
        root = packages.find(test.pkg)
    except BelvedereError:
        return f"{where}Package [{test.pkg}] for test node [{test.pkg}/{test.type}] does not exist"
    if find_script(root, test.type, test.pkg) is None:
        return f"{where}Test node [{test.pkg}/{test.type}] does not exist or is not executable"
    return None


def _run_with_retries(
    config: LaunchConfig,
    test: LaunchNode,
    package: str,
    packages: PackageIndex,
    options: RostestOptions,
    env: dict[str, str],
    runner: _Runner,
    case: CaseResult,
) -> None:
    name = str(test.test_name)
    retries = test.retry
    while True:
        runner.say(f"Running test [{name}]")
        results_file = Path(xml_results_file(package, name, env=env or None))
        if results_file.exists():
            runner.say(f"removing previous test results file [{results_file}]")
            results_file.unlink()
        words = [*shlex.split(test.args), f"{XML_OUTPUT_FLAG}{results_file}"]
        if options.text:
            words.append("--text")
        spec = replace(
            test,
            args=shlex.join(words),
            output="screen" if options.text else test.output,
        )
        ended = _run_once(config, spec, packages, options)
        if ended == "not started":
            case.failures.append(("AssertionError", f"test [{name}] failed to launch"))
            return
        timed_out = ended == "timeout"
        if timed_out:
            runner.say(f"test [{name}] timed out", error=True)
        else:
            runner.say(f"test [{name}] finished")
        if options.text and not timed_out:
            return
        failed = True
        results = None
        if not timed_out:
            results = read_results(results_file, package)
            if results is None:
                message = f"test [{name}] did not generate test results"
                if ended.startswith("exit"):
                    message += f" (it ended with {ended.replace('exit', 'exit code')})"
                case.failures.append(("AssertionError", message))
                runner.say(message, error=True)
                return
            runner.say(f"test [{name}] results are in [{results_file}]")
            failed = bool(results.errors or results.failures)
        if retries > 0 and failed:
            retries -= 1
            runner.say(f"test [{name}] failed, retrying. Retries left: {retries}")
            continue
        if results is None:  # the last try reached the time limit
            message = (
                f"max time [{test.time_limit:g}s] allotted for test [{name}] of type "
                f"[{test.pkg}/{test.type}]"
            )
            case.errors.append(("RLTestTimeoutException", message))
            runner.say(message, error=True)
            return
        runner.results.accumulate(results)
        runner.say(
            f"test [{name}] results summary: {results.errors} errors, "
            f"{results.failures} failures, {results.tests} tests"
        )
        return


def _run_once(
    config: LaunchConfig, test: LaunchNode, packages: PackageIndex, options: RostestOptions
) -> str:
    """Bring the launch up, run ``test`` to its end or its time limit, tear it all down:
    ``exit N``, ``timeout`` or ``not started``."""
    transport = open_clock_transport(options.address, clock=True)
    graph = Graph(sim_time=True, seed=options.seed, transport=transport)
    hold_time_base(config, graph)
    runtime = LaunchRuntime(config, graph, packages, headless=True, announce=True, lifecycle=True)
    try:
        runtime.start()
        process = runtime.start_test(test)
        if process is None:
            return "not started"
        deadline = time.monotonic() + test.time_limit
        looked = [0.0]
        timed_out = [False]

        def ended() -> bool:
            now = time.monotonic()
            if now - looked[0] < POLL_S:
                return False
            looked[0] = now
            runtime.poll_processes()
            if not process.alive():
                return True
            timed_out[0] = now > deadline
            return timed_out[0]

        graph.run(duration=None, rtf=options.rtf, until=ended)
        if timed_out[0]:
            return "timeout"
        code = process.exit_code or 0
        return f"exit {128 - code if code < 0 else code}"
    finally:
        runtime.close()
        graph.shutdown()


def _finish(
    path: Path,
    package: str,
    outname: str,
    options: RostestOptions,
    env: dict[str, str],
    runner: _Runner,
) -> RostestOutcome:
    failed_to_run = [c.name for c in runner.cases if c.failures]
    runner_errors = sum(bool(c.errors) for c in runner.cases)
    results = runner.results
    results_file = None
    if not options.text:
        results_file = xml_results_file(package, outname, is_rostest=True, env=env or None)
        own = SuiteResult(
            "unittest.suite.TestSuite",
            tests=len(runner.cases),
            failures=len(failed_to_run),
            errors=runner_errors,
            time=sum(c.time for c in runner.cases),
            cases=runner.cases,
            system_out="\n".join(runner.log) + "\n",
        )
        write_results(Path(results_file), own)
    shown = replace(results, errors=results.errors + runner_errors)
    summary = summary_text("ROSTEST", shown, failed_to_run)
    if failed_to_run or runner_errors:
        status = 1
    elif results.errors or results.failures:
        status = 2
    else:
        status = 0
    return RostestOutcome(
        file=str(path),
        package=package,
        status=status,
        summary=summary,
        results_file=results_file,
        tests=results.tests,
        failures=results.failures + len(failed_to_run),
        errors=results.errors + runner_errors,
    )
