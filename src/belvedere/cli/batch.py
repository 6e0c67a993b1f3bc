"""``belvedere batch SPEC.yaml -o OUT.csv``: many headless runs, one CSV row each.

The spec (docs/launch-and-run.md, "Many runs") names one run (``sim:`` or ``launch:`` and
a ``duration``), the values that vary (their cartesian product is the batch) and the
columns each run reports.
Runs go to ``--workers`` local processes, or to a Ray cluster with ``--ray``.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from belvedere.batch import Progress, plot_rows, read_spec, run_local, run_ray, write_csv
from belvedere.cli._args import worker_count
from belvedere.cli._report import notice
from belvedere.errors import BelvedereError

__all__ = ["add_parser", "run"]


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser(
        "batch",
        parents=[common],
        help="run many headless simulations from a spec, one CSV row each",
        description="Run every combination of a spec's varied values as its own headless "
        "simulation (--rtf max, a graph of its own) and write one CSV row per run.",
    )
    p.add_argument("spec", metavar="SPEC.yaml", help="the batch spec (see docs/launch-and-run.md)")
    p.add_argument("-o", "--output", required=True, metavar="OUT.csv", help="the rows' CSV file")
    p.add_argument(
        "--workers",
        type=worker_count,
        metavar="N",
        help="runs at a time on this machine (default: the number of cores)",
    )
    p.add_argument(
        "--ray",
        metavar="auto|ADDRESS",
        help="run on a Ray cluster instead (auto: the one this machine joined)",
    )
    p.add_argument("--plot", metavar="OUT.png", help="plot each column against each varied value")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    spec = read_spec(args.spec)
    output = Path(args.output)
    if not output.parent.is_dir():
        msg = f"-o {args.output}: no folder {output.parent}"
        raise BelvedereError(msg)
    if args.ray and args.workers:
        msg = "--workers is for local runs; Ray places --ray's runs itself"
        raise BelvedereError(msg)
    bag_dir = None
    if any(r.bag for r in spec.runs):
        bag_dir = output.resolve().with_suffix(".bags")
        bag_dir.mkdir(exist_ok=True)
    progress = Progress(len(spec.runs), sys.stderr)
    if args.ray:
        rows = run_ray(spec, args.ray, progress, bag_dir=bag_dir)
    else:
        rows = run_local(spec, args.workers or os.cpu_count() or 1, progress, bag_dir=bag_dir)
    write_csv(output, spec, rows)
    if args.plot:
        plot_rows(Path(args.plot), spec, rows)
    failed = sum(r["status"] != "ok" for r in rows)
    notice(f"batch: {len(rows)} runs, {failed} failed; rows in {output}")
    return 0
