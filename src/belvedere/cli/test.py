"""``belvedere test [PKG] FILE.test … [arg:=value …]``: rostest.

Each file's ``<test>`` nodes run as rostest runs them (:mod:`belvedere.runtime._rostest`):
the launch up in simulated time on a graph of its own, each test node to its end or its
``time-limit``, pass or fail from its results file, rostest's summary printed and its JUnit
file written. Several files run side by side, each a ``belvedere test`` process of its own,
on ``--workers`` local processes or a Ray cluster (``--ray``), as ``belvedere batch`` runs.
The exit status is rostest's: 0 passed, 1 a test failed to run, 2 a test failed (the worst
of the files').
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

from belvedere.cli._args import mappings_only, worker_count
from belvedere.cli._script import parse_rtf
from belvedere.cli._tool import add_graph_options, graph_address
from belvedere.errors import BelvedereError, did_you_mean
from belvedere.packages import PackageIndex, find_package_root
from belvedere.runtime import GraphAddress
from belvedere.runtime._rostest import RostestOptions, run_rostest

__all__ = ["add_parser", "run"]

_GRAPH_ENV = ("BELVEDERE_DOMAIN", "BELVEDERE_ENDPOINT", "BELVEDERE_CONNECT", "BELVEDERE_LISTEN")


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser(
        "test",
        parents=[common],
        help="run rostest files (.test/.launch with <test> nodes)",
        description="Run the <test> nodes of rostest files as rostest does: belvedere test "
        "PKG FILE.test [name:=value …] or belvedere test PATH.test … Each test runs with the "
        "launch brought up fresh, in simulated time on a graph of its own, to its end or its "
        "time-limit; rostest's summary is printed and its JUnit XML written (--results DIR, "
        "default ROS_TEST_RESULTS_DIR or ~/.ros/test_results). Exit status: 0 passed, "
        "1 a test failed to run, 2 a test failed.",
    )
    p.add_argument("words", nargs="+", metavar="[PKG] FILE", help="a package and files, or paths")
    p.add_argument("--results", metavar="DIR", help="the results folder (PKG/ below it)")
    p.add_argument(
        "--text", action="store_true", help="the test nodes print unittest's report, no XML"
    )
    p.add_argument(
        "--workers", type=worker_count, metavar="N", help="files at a time here (default: cores)"
    )
    p.add_argument("--ray", metavar="auto|ADDRESS", help="run the files on a Ray cluster")
    p.add_argument(
        "--rtf",
        type=parse_rtf,
        default=None,
        metavar="max|N",
        help="the simulation's real-time factor (default: max, as fast as the CPU allows)",
    )
    p.add_argument("--seed", type=int, default=0, help="seed of the simulation's randomness")
    add_graph_options(p, hosts=False, ros_master=False)
    p.set_defaults(run=run)


@dataclass(frozen=True)
class _FileJob:
    """One file for a worker: run as a ``belvedere test`` process of its own."""

    file: str
    """Relative to ``folder`` (where a Ray task's shipped copy is)."""
    folder: str
    argv: tuple[str, ...]
    """Its options and ``name:=value`` arguments."""


@dataclass(frozen=True)
class _FileDone:
    file: str
    status: int
    stdout: str
    stderr: str


def _run_job(job: _FileJob) -> _FileDone:
    return _run_job_in(job, Path(job.folder))


def _ray_job(job: _FileJob) -> _FileDone:
    return _run_job_in(job, Path.cwd())


def _run_job_in(job: _FileJob, folder: Path) -> _FileDone:
    env = {k: v for k, v in os.environ.items() if k not in _GRAPH_ENV}
    proc = subprocess.run(
        [sys.executable, "-m", "belvedere", "test", job.file, *job.argv],
        cwd=folder,
        env=env,
        stdin=subprocess.DEVNULL,
        capture_output=True,
        text=True,
        check=False,
    )
    return _FileDone(job.file, proc.returncode, proc.stdout, proc.stderr)


def _files(words: list[str], packages: PackageIndex) -> list[Path]:
    """The test files the words name: paths, or a package then files in it."""
    if all(os.path.isfile(w) for w in words):
        return [Path(w) for w in words]
    if os.path.isfile(words[0]):
        missing = next(w for w in words if not os.path.isfile(w))
        msg = f"test file {missing!r} does not exist"
        raise BelvedereError(msg)
    if len(words) == 1:
        msg = f"test file {words[0]!r} does not exist"
        raise BelvedereError(msg, hint="or give a package and a file: test PKG FILE.test")
    root = packages.find(words[0])
    found = []
    for word in words[1:]:
        direct = root / word
        if direct.is_file():
            found.append(direct)
            continue
        below = sorted(p for p in root.rglob(Path(word).name) if p.is_file())
        if not below:
            names = sorted({p.name for p in root.rglob("*.test")})
            msg = f"no test file {word!r} in package {words[0]!r} ({root})"
            raise BelvedereError(
                msg, hint=did_you_mean(word, names) or f"its files: {', '.join(names) or 'none'}"
            )
        found.append(below[0])
    return found


def run(args: argparse.Namespace) -> int:
    words = [w for w in args.words if ":=" not in w]
    mappings = mappings_only([w for w in args.words if ":=" in w])
    if not words:
        msg = "test: expects a test file, or a package and a test file"
        raise BelvedereError(msg)
    packages = PackageIndex.from_environment(
        package_path=args.package_path, near=words[0] if os.path.exists(words[0]) else None
    )
    files = _files(words, packages)
    if args.ray and args.workers:
        msg = "--workers is for local runs; Ray places --ray's files itself"
        raise BelvedereError(msg)
    if len(files) > 1 or args.ray:
        return _run_many(files, args)
    path = files[0]
    address = graph_address(args)
    if address.endpoint is None and address.domain is None:
        address = GraphAddress(endpoint=f"tcp/127.0.0.1:{_free_port()}")
    options = RostestOptions(
        address=address,
        results=Path(args.results).resolve() if args.results else None,
        text=args.text,
        rtf=args.rtf,
        seed=args.seed,
    )
    outcome = run_rostest(path, packages.with_workspace_of(path), options, args=mappings)
    if args.text:  # the test nodes' own reports are the result, as with rostest --text
        sys.stdout.write("WARNING: overall test result is not accurate when --text is enabled\n")
    else:
        sys.stdout.write(outcome.summary + "\n")
    return outcome.status


def _run_many(files: list[Path], args: argparse.Namespace) -> int:
    """Each file a ``belvedere test`` process of its own (its own graph), side by side."""
    # a Ray task gets this folder: the files' packages, so their scripts travel with them
    roots = [find_package_root(f.resolve()) or f.resolve().parent for f in files]
    folder = Path(os.path.commonpath([str(r) for r in roots]))
    argv: list[str] = [w for w in args.words if ":=" in w]
    for path in args.package_path or []:
        argv += ["--package-path", str(Path(path).resolve())]
    if args.results:
        argv += ["--results", str(Path(args.results).resolve())]
    if args.text:
        argv.append("--text")
    if args.rtf is not None:
        argv += ["--rtf", repr(args.rtf)]
    argv += ["--seed", str(args.seed), "-q"]
    jobs = [_FileJob(str(f.resolve().relative_to(folder)), str(folder), tuple(argv)) for f in files]

    def done(result: _FileDone) -> None:
        sys.stderr.write(f"test: {result.file}: exit {result.status}\n")

    from belvedere.batch import map_local, map_ray

    if args.ray:
        results = map_ray(
            _ray_job,
            jobs,
            args.ray,
            folder,
            done,
            lost=lambda job, err: _FileDone(job.file, 1, "", f"Ray: {err}"),
        )
    else:
        results = map_local(_run_job, jobs, args.workers or os.cpu_count() or 1, done)
    for result in results:
        sys.stdout.write(f"==== {result.file}\n{result.stdout}")
        if result.status not in (0, 2):
            sys.stderr.write(result.stderr[-4000:])
    statuses = {r.status for r in results}
    if statuses <= {0}:
        return 0
    return 2 if statuses <= {0, 2} else 1


def _free_port() -> int:
    """A port nobody listens on now: the tests' graphs meet there, alone (rostest, too,
    starts its own master on a free port)."""
    import socket

    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port
