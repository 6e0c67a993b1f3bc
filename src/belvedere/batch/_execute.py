"""One batch run: a ``belvedere sim``/``belvedere launch`` process of its own, headless at
``--rtf max`` on a graph of its own, its topics echoed, and the row its messages give.

A run never raises: a failing process, a run past its wall-clock timeout or a column its
messages cannot give is said in the row's ``status`` and ``error``. This function is what a
local worker and a Ray task both call, so it takes and returns plain picklable values.
"""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any
from xml.sax.saxutils import quoteattr

import yaml

from belvedere.batch._measure import MeasureError, evaluate
from belvedere.batch._spec import RunDescription
from belvedere.errors import BelvedereError
from belvedere.packages import PackageIndex, workspace_dirs

__all__ = ["Row", "execute_run"]

Row = dict[str, Any]
"""column → value, the columns of :attr:`BatchSpec.columns`."""

_Loader: Any = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
_GRAPH_ENV = (
    "BELVEDERE_DOMAIN",
    "BELVEDERE_ENDPOINT",
    "BELVEDERE_CONNECT",
    # a graph across hosts (graph/_hosts.py): scouting would let runs find one another
    "BELVEDERE_LISTEN",
    "BELVEDERE_TOKEN",
    "BELVEDERE_DISCOVER",
)


def execute_run(run: RunDescription, folder: Path, *, bag_dir: Path | None = None) -> Row:
    """Run ``run`` with ``folder`` (the spec's) as its working directory; its row."""
    row: Row = {"run": run.index, **dict(run.values)}
    started = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="belvedere-batch-") as scratch:
        try:
            argv = _command(run, folder, Path(scratch), bag_dir)
        except BelvedereError as err:
            return _outcome(row, "failed", err.message, started, run)
        status, error, stdout = _start(argv, folder, run.timeout)
    _outcome(row, status, error, started, run)
    if status != "ok":
        return row
    messages = _messages(stdout, _topics(run))
    errors = [error] if error else []
    for measure in run.measures:
        try:
            row[measure.name] = evaluate(measure, messages, folder)
        except MeasureError as err:
            errors.append(err.message)
    row["error"] = "; ".join(errors)
    return row


def _outcome(row: Row, status: str, error: str, started: float, run: RunDescription) -> Row:
    row.update(status=status, error=error, wall_s=round(time.monotonic() - started, 3))
    for measure in run.measures:
        row.setdefault(measure.name, None)
    return row


def _topics(run: RunDescription) -> list[str]:
    return sorted({t for m in run.measures for t in m.topics})


def _command(run: RunDescription, folder: Path, scratch: Path, bag_dir: Path | None) -> list[str]:
    words = list(run.command)
    if run.kind == "launch" and (run.params or run.bag):
        words = _wrapped_launch(run, words, folder, scratch, bag_dir)
    elif run.args:
        words += [f"{name}:={value}" for name, value in run.args]
    argv = [sys.executable, "-m", "belvedere", run.kind, *words, "-q", "--headless"]
    argv += ["--rtf", "max", "--duration", repr(run.duration), "--seed", str(run.seed)]
    argv += ["--endpoint", f"tcp/127.0.0.1:{_free_port()}"]
    for spec in run.pubs:
        argv += ["--pub", spec]
    for topic in _topics(run):
        argv += ["--echo", topic]
    return argv


def _wrapped_launch(
    run: RunDescription, words: list[str], folder: Path, scratch: Path, bag_dir: Path | None
) -> list[str]:
    """The run's launch file inside one of the batch's own: roslaunch's ``<include>`` with
    the run's args, its ``<param>`` after (a later declaration wins, as in roslaunch) and a
    ``rosbag record`` node when the run records a bag."""
    positional = []
    for word in words:
        if word.startswith("-") or ":=" in word:
            break
        positional.append(word)
    rest = words[len(positional) :]
    options = [rest[i + 1] for i, w in enumerate(rest[:-1]) if w == "--package-path"]
    target = _launch_path(positional, folder, options)
    lines = ["<launch>", f"  <include file={quoteattr(str(target))}>"]
    lines += [f"    <arg name={quoteattr(n)} value={quoteattr(v)}/>" for n, v in run.args]
    lines.append("  </include>")
    for name, value in run.params:
        kind = "" if isinstance(value, str) else f" type={quoteattr(_param_type(value))}"
        text = str(value).lower() if isinstance(value, bool) else str(value)
        lines.append(f"  <param name={quoteattr(name)} value={quoteattr(text)}{kind}/>")
    if run.bag and bag_dir is not None:
        bag = bag_dir / f"run-{run.index:04d}.bag"
        lines.append(
            '  <node pkg="rosbag" type="record" name="belvedere_batch_bag" '
            f"args={quoteattr(f'-a -O {bag}')}/>"
        )
    lines.append("</launch>")
    wrapper = scratch / f"run-{run.index:04d}.launch"
    wrapper.write_text("\n".join(lines) + "\n", encoding="utf-8")
    workspace = [str(p) for p in workspace_dirs(target)]
    return [str(wrapper), *rest, *(w for p in workspace for w in ("--package-path", p))]


def _param_type(value: Any) -> str:
    if isinstance(value, bool):
        return "bool"
    return "int" if isinstance(value, int) else "double"


def _launch_path(positional: list[str], folder: Path, package_path: list[str]) -> Path:
    if len(positional) == 1:
        path = folder / positional[0]
        if not path.is_file():
            msg = f"launch file {positional[0]!r} does not exist (in {folder})"
            raise BelvedereError(msg)
        return path
    if len(positional) != 2:
        msg = f"launch: expects 'PKG FILE' or a launch file, got {positional}"
        raise BelvedereError(msg)
    packages = PackageIndex.from_environment(
        package_path=[folder / p for p in package_path], near=folder / "spec"
    )
    root = packages.find(positional[0])
    direct = root / positional[1]
    if direct.is_file():
        return direct
    found = sorted(p for p in root.rglob(Path(positional[1]).name) if p.is_file())
    if not found:
        msg = f"no launch file {positional[1]!r} in package {positional[0]!r}"
        raise BelvedereError(msg)
    return found[0]


def _free_port() -> int:
    """A port nobody listens on now: the run's graph meets there, alone."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


def _start(argv: list[str], folder: Path, timeout: float) -> tuple[str, str, str]:
    """(status, error, stdout) of the run's process."""
    env = {k: v for k, v in os.environ.items() if k not in _GRAPH_ENV}
    proc = subprocess.Popen(
        argv,
        cwd=folder,
        env=env,
        stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # its nodes' processes are stopped with it
    )
    try:
        stdout, stderr = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        return "timeout", f"stopped after {timeout:g} s of wall-clock time", ""
    if proc.returncode != 0:
        return "failed", f"exit {proc.returncode}: {_error_line(stderr)}", stdout
    return "ok", "", stdout


def _error_line(stderr: str) -> str:
    lines = [line.strip() for line in stderr.splitlines() if line.strip()]
    errors = [line for line in lines if "error:" in line or "Error" in line]
    return (errors or lines or ["no output"])[-1]


def _messages(stdout: str, topics: list[str]) -> Mapping[str, list[Any]]:
    """The echoed messages by topic (one topic: unlabelled; several: each ``# TOPIC``)."""
    found: dict[str, list[Any]] = {t: [] for t in topics}
    for doc in stdout.split("\n---\n"):
        doc = doc.strip("\n")
        if not doc:
            continue
        topic = topics[0] if len(topics) == 1 else ""
        if len(topics) > 1 and doc.startswith("# "):
            first, _, doc = doc.partition("\n")
            topic = first[2:].strip()
        if topic in found:
            found[topic].append(yaml.load(doc, Loader=_Loader))
    return found
