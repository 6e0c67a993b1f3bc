"""The differential harness for rospy: the same learner scripts under Debian's ROS 1 and
under belvedere must print the same lines.

Under ROS, a real roscore on a port of its own (with a ROS_HOME of its own) and each script
run as rosrun runs it: ``/usr/bin/python3 script.py args`` with ``/usr/bin`` first on PATH.
Time is the wall clock's, as with a bare roscore. Under belvedere, each script is a
``python -m belvedere run script.py args`` process: the first provides the graph (as roscore,
in wall time), the others join it (they inherit BELVEDERE_ENDPOINT/DOMAIN).

Every script's stdout and stderr are captured apart and compared apart, line by line: two
processes print concurrently, so only each one's own streams have an order. What is masked
is what differs from run to run even under ROS: the times in log lines, anonymous-name
suffixes and pids; and what only rospy's own code can print: the frames of its files in the
traceback it logs when a service handler raises. A case may leave out lines of rospy's
internals (``Case.ignore``).
"""

from __future__ import annotations

import difflib
import os
import re
import shutil
import socket
import subprocess
import sys
import tempfile
import threading
import time
import xmlrpc.client
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager, suppress
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from tests.debian_ros import ROS_PYTHON, ROSCORE, missing_debian_ros

__all__ = [
    "CASES",
    "SCRIPTS",
    "Case",
    "Master",
    "Output",
    "Script",
    "differences",
    "mask",
    "missing_oracle",
    "run_belvedere",
    "run_ros",
]

SCRIPTS = Path(__file__).parent / "scripts"
REPO = Path(__file__).parents[2]
CASE_TIMEOUT = 30.0
"""Seconds a case may take before its processes are killed (a hang is a failure, not a wait)."""


@dataclass(frozen=True)
class Script:
    """One process of a case: a script of ``scripts/`` and its command-line arguments."""

    file: str
    args: tuple[str, ...] = ()
    after: tuple[str, str] | None = None
    """Start only once the script labelled ``after[0]`` has printed the line ``after[1]``."""
    label: str = ""

    @property
    def name(self) -> str:
        return self.label or self.file.removesuffix(".py")


@dataclass(frozen=True)
class Case:
    name: str
    scripts: tuple[Script, ...]
    ignore: str | None = None
    """Lines (after masking) left out of the comparison, with the reason in the case."""

    def __post_init__(self) -> None:
        labels = [s.name for s in self.scripts]
        if len(set(labels)) != len(labels):
            msg = f"case {self.name}: two scripts labelled alike: {labels}"
            raise ValueError(msg)


CASES: tuple[Case, ...] = (
    Case("chatter", (Script("talker.py"), Script("listener.py"))),
    Case(
        "latched",
        (
            Script("latched_talker.py"),
            Script("late_listener.py", after=("latched_talker", "published latched")),
        ),
    ),
    Case("cmd_vel", (Script("drive.py"), Script("cmd_listener.py"))),
    Case("wait_for_message", (Script("ready_publisher.py"), Script("waiter.py"))),
    # a client whose request does not serialize has opened a connection and drops it: the
    # server logs that or not, as the timing goes
    Case(
        "services",
        (
            Script("service_server.py"),
            Script("service_client.py", after=("service_server", "services up")),
        ),
        ignore=r"^\[ERROR\] \[[TIME, ]+\]: incoming connection failed: unable to receive data "
        r"from sender, check sender's logs for details$",
    ),
    Case(
        "params",
        (Script("params.py", ("_speed:=0.5", "_mode:=fast", "_flag:=true", "_gains:=[1, 2]")),),
    ),
    Case("names", (Script("names.py"),)),
    Case(
        "names_remapped",
        (
            Script(
                "names.py",
                ("plain_arg", "chatter:=/other", "__name:=renamed", "__ns:=/robot1", "_rate:=10"),
            ),
        ),
    ),
    Case("anonymous", (Script("anonymous.py"),)),
    Case("time", (Script("time_demo.py"),)),
    Case("shutdown", (Script("shutdown_hooks.py"),)),
    Case("logging", (Script("logs.py"),)),
    # rospy's own debug lines (its pid, the ports it bound and connects to, its logger
    # services, connections closing at the end, some of them racing the exit) are its
    # internals, not the API: only the script's own debug lines (all "script: …") count
    Case(
        "debug_level",
        (Script("debug_level.py"),),
        ignore=r"^\[DEBUG\] \[[TIME, ]+\]: (?!script: )",
    ),
    Case("header_seq", (Script("header_pub.py"), Script("header_sub.py"))),
)


@dataclass(frozen=True)
class Output:
    stdout: str
    stderr: str
    returncode: int | None
    """None: killed after :data:`CASE_TIMEOUT`."""


def missing_oracle() -> str | None:
    """Why the ROS side cannot run here, or None."""
    return missing_debian_ros("rospy, std_srvs.srv, geometry_msgs.msg")


# --- masking and comparing -------------------------------------------------------------------
_LOG_TIME = re.compile(r"^(\[(?:DEBUG|INFO|WARN|ERROR|FATAL)\] \[)([0-9., ]+)(\]: )", re.M)
_ANON = re.compile(r"(\w)_\d+_\d{10,}")
_NUMBER = re.compile(r"\d+\.\d+")
_PID = re.compile(r"\bpid\[\d+\]")
_LIBRARY_FRAME = re.compile(
    "'  File \"(?!" + re.escape(str(SCRIPTS) + os.sep) + r""")[^"]*", line \d+, in [^']*', """
)
"""A frame of the library's own code in the traceback list rospy logs when a service handler
raises ("Error processing request"): rospy's file and line, not the user's."""


def mask(text: str) -> str:
    """The output with what changes from run to run under ROS itself replaced."""
    text = _LOG_TIME.sub(lambda m: m[1] + _NUMBER.sub("TIME", m[2]) + m[3], text)
    text = _ANON.sub(r"\1_ANON", text)
    text = _PID.sub("pid[PID]", text)
    return _LIBRARY_FRAME.sub("", text)


def lines(case: Case, text: str) -> list[str]:
    """The masked lines of one stream that ``case`` compares."""
    ignore = re.compile(case.ignore) if case.ignore else None
    return [x for x in mask(text).splitlines() if ignore is None or not ignore.search(x)]


def differences(
    case: Case, expected: Mapping[str, Output], got: Mapping[str, Output]
) -> tuple[int, list[str]]:
    """(lines compared, one diff per stream that differs) between two runs of ``case``."""
    compared = 0
    found: list[str] = []
    for script in case.scripts:
        want, have = expected[script.name], got[script.name]
        for stream in ("stdout", "stderr"):
            a = lines(case, getattr(want, stream))
            b = lines(case, getattr(have, stream))
            compared += len(a)
            if a != b:
                diff = difflib.unified_diff(
                    a,
                    b,
                    f"ROS {script.name} {stream}",
                    f"belvedere {script.name} {stream}",
                    lineterm="",
                )
                found.append("\n".join(diff))
        if want.returncode != have.returncode:
            found.append(
                f"{script.name}: exit status {have.returncode}, ROS's is {want.returncode}"
            )
    return compared, found


# --- running processes -----------------------------------------------------------------------
class _Running:
    """A started script whose two streams are read by threads as they come (so another
    script can start on a line of its stdout)."""

    def __init__(self, argv: Sequence[str], env: Mapping[str, str], cwd: Path) -> None:
        self.process = subprocess.Popen(
            list(argv),
            env=dict(env),
            cwd=cwd,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        self.out: list[str] = []
        self.err: list[str] = []
        self.changed = threading.Condition()
        assert self.process.stdout is not None
        assert self.process.stderr is not None
        self.readers = [
            threading.Thread(target=self._read, args=(self.process.stdout, self.out), daemon=True),
            threading.Thread(target=self._read, args=(self.process.stderr, self.err), daemon=True),
        ]
        for reader in self.readers:
            reader.start()

    def _read(self, stream: object, into: list[str]) -> None:
        for line in stream:  # type: ignore[attr-defined]
            with self.changed:
                into.append(line)
                self.changed.notify_all()
        with self.changed:
            self.changed.notify_all()

    def wait_line(self, line: str, deadline: float) -> bool:
        with self.changed:
            while True:
                if any(x.rstrip("\n") == line for x in self.out):
                    return True
                if self.process.poll() is not None and not any(r.is_alive() for r in self.readers):
                    return False
                left = deadline - time.monotonic()
                if left <= 0:
                    return False
                self.changed.wait(min(left, 0.1))

    def finish(self, deadline: float) -> Output:
        try:
            code: int | None = self.process.wait(timeout=max(0.0, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
            code = None
        for reader in self.readers:
            reader.join(timeout=5)
        return Output("".join(self.out), "".join(self.err), code)

    def kill(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()


def _run_case(
    case: Case,
    start: Mapping[str, tuple[list[str], dict[str, str]]],
    *,
    first_ready: object = None,
) -> dict[str, Output]:
    """Start the scripts of ``case`` (``start``: argv and env by label) in order, each
    ``after`` its line; collect every output. ``first_ready(deadline)`` is waited for after
    the first script starts."""
    deadline = time.monotonic() + CASE_TIMEOUT
    running: dict[str, _Running] = {}
    outputs: dict[str, Output] = {}
    try:
        for i, script in enumerate(case.scripts):
            if script.after is not None:
                other, line = script.after
                if not running[other].wait_line(line, deadline):
                    break  # the other script's output will show why
            argv, env = start[script.name]
            running[script.name] = _Running(argv, env, SCRIPTS)
            if i == 0 and first_ready is not None:
                first_ready(deadline)  # type: ignore[operator]
        for script in case.scripts:
            if script.name in running:
                outputs[script.name] = running[script.name].finish(deadline)
            else:
                outputs[script.name] = Output("", "(not started)\n", None)
    finally:
        for proc in running.values():
            proc.kill()
    return outputs


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


class Master:
    """A Debian roscore on a free port of its own, with a ROS_HOME of its own."""

    def __init__(self, home: Path) -> None:
        self.home = home
        self.port = free_port()
        self.uri = f"http://127.0.0.1:{self.port}"
        self.env = {
            "PATH": "/usr/bin:/bin:" + os.environ.get("PATH", ""),
            "HOME": os.environ.get("HOME", str(home)),
            "LANG": "C.UTF-8",
            "ROS_MASTER_URI": self.uri,
            "ROS_HOME": str(home),
            "PYTHONUNBUFFERED": "1",
        }
        self.process = subprocess.Popen(
            [str(ROSCORE), "-p", str(self.port)],
            env=self.env,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            start_new_session=True,
        )
        self.proxy = xmlrpc.client.ServerProxy(self.uri)
        self._wait_for_rosout()
        self.initial_params = set(self._call("getParamNames"))

    def _call(self, method: str, *args: object) -> Any:
        code, text, value = getattr(self.proxy, method)("/rospy_oracle", *args)
        if code != 1:
            msg = f"roscore {method}{args}: {text}"
            raise RuntimeError(msg)
        return value

    def _wait_for_rosout(self) -> None:
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            if self.process.poll() is not None:
                msg = f"roscore exited with {self.process.returncode}"
                raise RuntimeError(msg)
            try:
                answer: Any = self.proxy.lookupNode("/rospy_oracle", "/rosout")
                code = answer[0]
            except OSError:
                code = 0
            if code == 1:
                return
            time.sleep(0.1)
        self.close()
        msg = "roscore did not come up (no /rosout) within 30 s"
        raise RuntimeError(msg)

    def reset(self) -> None:
        """Back to a fresh roscore's parameters (what one case set is gone for the next)."""
        for name in set(self._call("getParamNames")) - self.initial_params:
            if name.startswith("/"):
                with suppress(RuntimeError):  # a parent deleted first took it along
                    self._call("deleteParam", name)

    def close(self) -> None:
        if self.process.poll() is None:
            os.killpg(self.process.pid, 15)
            try:
                self.process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                os.killpg(self.process.pid, 9)
                self.process.wait()


@contextmanager
def master() -> Iterator[Master]:
    home = Path(tempfile.mkdtemp(prefix="rospy-oracle-"))
    core = Master(home)
    try:
        yield core
    finally:
        core.close()
        shutil.rmtree(home, ignore_errors=True)


def run_ros(case: Case, core: Master) -> dict[str, Output]:
    """``case`` under Debian's ROS, on ``core`` (reset first)."""
    core.reset()
    start = {
        s.name: ([str(ROS_PYTHON), str(SCRIPTS / s.file), *s.args], dict(core.env))
        for s in case.scripts
    }
    return _run_case(case, start)


def _endpoint_port(endpoint: str) -> int | None:
    match = re.fullmatch(r"tcp/[^:]+:(\d+)", endpoint)
    return int(match[1]) if match else None


def run_belvedere(case: Case, rtf: str = "1") -> dict[str, Output]:
    """``case`` under belvedere: a ``belvedere run`` per script on the test's graph (from
    BELVEDERE_ENDPOINT/BELVEDERE_DOMAIN); the first one provides it."""
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join(
            filter(None, [str(REPO / "src"), os.environ.get("PYTHONPATH")])
        ),
        "PYTHONUNBUFFERED": "1",
    }
    start = {
        s.name: (
            [
                sys.executable,
                "-m",
                "belvedere",
                "run",
                "-q",
                "--headless",
                "--rtf",
                rtf,
                str(SCRIPTS / s.file),
                *s.args,
            ],
            env,
        )
        for s in case.scripts
    }
    port = _endpoint_port(os.environ.get("BELVEDERE_ENDPOINT", ""))

    def listening(deadline: float) -> None:
        """The first process provides the graph: the others join only once it listens."""
        if port is None or len(case.scripts) == 1:
            return
        while time.monotonic() < deadline:
            with socket.socket() as s:
                if s.connect_ex(("127.0.0.1", port)) == 0:
                    return
            time.sleep(0.05)

    return _run_case(case, start, first_ready=listening)


@dataclass
class Tally:
    """What a test session compared (for the report)."""

    cases: int = 0
    lines: int = 0
    differences: list[str] = field(default_factory=list)


def _show(case: Case, outputs: Mapping[str, Output]) -> str:
    parts = []
    for script in case.scripts:
        out = outputs[script.name]
        parts.append(f"== {case.name}/{script.name} exit {out.returncode}")
        parts += [f"  out| {line}" for line in lines(case, out.stdout)]
        parts += [f"  err| {line}" for line in lines(case, out.stderr)]
    return "\n".join(parts)


def main(argv: Sequence[str]) -> int:
    """``python -m tests.ros1.rospy_oracle [--belvedere] [--repeat N] [CASE…]``: print the
    masked outputs of the cases (for writing and checking them)."""
    words = list(argv)
    on_belvedere = "--belvedere" in words
    repeat = 1
    if "--repeat" in words:
        at = words.index("--repeat")
        repeat = int(words[at + 1])
        del words[at : at + 2]
    names = [w for w in words if not w.startswith("--")]
    cases = [c for c in CASES if not names or c.name in names]
    stable = True
    with master() if not on_belvedere else _no_master() as core:
        for case in cases:
            seen: list[str] = []
            for _ in range(repeat):
                outputs = run_ros(case, core) if core is not None else run_belvedere(case)
                seen.append(_show(case, outputs))
            sys.stdout.write(seen[0] + "\n")
            for other in seen[1:]:
                if other != seen[0]:
                    stable = False
                    diff = difflib.unified_diff(
                        seen[0].splitlines(), other.splitlines(), lineterm=""
                    )
                    sys.stdout.write(f"!! {case.name}: a repeated run differs:\n")
                    sys.stdout.write("\n".join(diff) + "\n")
    return 0 if stable else 1


@contextmanager
def _no_master() -> Iterator[Master | None]:
    yield None


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
