"""Where a batch's runs execute: a local pool of ``--workers`` processes (each run is a
process of its own; the pool's threads only wait on them) or Ray tasks on a cluster.

Either way rows arrive as runs finish, to ``on_row``, and come back in run order: a row
depends on its run alone (its seed decides it), never on who ran it or when.
"""

from __future__ import annotations

import concurrent.futures
import functools
import ipaddress
import logging
import multiprocessing
import socket
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

from belvedere.batch._execute import Row, execute_run
from belvedere.batch._spec import BatchSpec, RunDescription
from belvedere.errors import BelvedereError

__all__ = ["RAY_RETRIES", "map_local", "map_ray", "run_local", "run_ray"]

RAY_RETRIES = 3
"""How many times Ray runs a task again whose worker or node was lost mid-run."""

OnRow = Callable[[Row], None]
T = TypeVar("T")
R = TypeVar("R")


def map_local(
    work: Callable[[T], R], items: list[T], workers: int, on_done: Callable[[R], None]
) -> list[R]:
    """``work(item)`` for every item, at most ``workers`` at a time in processes of their
    own (``work`` and the items must pickle); results to ``on_done`` as they finish, and
    back in the items' order.

    The pool's workers are processes, not threads: what a run gives is parsed where it
    ran, and parsing in threads of one process would take turns on its GIL."""
    results: list[R | None] = [None] * len(items)
    context = multiprocessing.get_context("spawn")  # no threads of this process forked
    with concurrent.futures.ProcessPoolExecutor(max(1, workers), mp_context=context) as pool:
        futures = {pool.submit(work, item): i for i, item in enumerate(items)}
        for future in concurrent.futures.as_completed(futures):
            result = future.result()
            on_done(result)
            results[futures[future]] = result
    return [r for r in results if r is not None]


def run_local(
    spec: BatchSpec, workers: int, on_row: OnRow, *, bag_dir: Path | None = None
) -> list[Row]:
    """Every run of ``spec``, at most ``workers`` at a time on this machine."""
    work = functools.partial(_local_run, folder=spec.folder, bag_dir=bag_dir)
    return map_local(work, list(spec.runs), workers, on_row)


def _local_run(run: RunDescription, *, folder: Path, bag_dir: Path | None) -> Row:
    return execute_run(run, folder, bag_dir=bag_dir)


def _ray_task(run: RunDescription, *, bag_dir: Path | None) -> Row:
    """A run on a Ray worker: its working directory is the spec's folder Ray shipped."""
    return execute_run(run, Path.cwd(), bag_dir=bag_dir)


def run_ray(
    spec: BatchSpec, address: str, on_row: OnRow, *, bag_dir: Path | None = None
) -> list[Row]:
    """Every run of ``spec`` as a Ray task on the cluster at ``address`` (``auto``: the one
    this machine belongs to), the spec's folder shipped as each task's working directory."""
    work = functools.partial(_ray_task, bag_dir=bag_dir)
    rows = map_ray(
        work,
        list(spec.runs),
        address,
        spec.folder,
        on_row,
        lost=lambda run, err: _lost(spec, run, err),
    )
    return sorted(rows, key=lambda r: int(r["run"]))


def map_ray(
    work: Callable[[T], R],
    items: list[T],
    address: str,
    folder: Path,
    on_done: Callable[[R], None],
    *,
    lost: Callable[[T, Exception], R],
) -> list[R]:
    """``work(item)`` for every item as a Ray task on the cluster at ``address``, each in
    ``folder`` shipped as its working directory (a task whose worker was lost runs again,
    :data:`RAY_RETRIES` times; then ``lost`` gives its result); results to ``on_done`` as
    they finish, and back in the items' order."""
    try:
        import ray  # an optional extra: only --ray needs it
    except ImportError:
        msg = "--ray needs Ray, which is not installed"
        raise BelvedereError(msg, hint="pip install 'belvedere[ray]'") from None
    runtime_env: dict[str, Any] = {
        "working_dir": str(folder),
        "excludes": [".git", "*.bag", "*.mcap", "__pycache__"],
    }
    host = address.removeprefix("ray://").rpartition(":")[0].strip("[]")
    try:
        loopback = ipaddress.ip_address(host).is_loopback
    except ValueError:
        loopback = False
    port = address.rpartition(":")[2]
    if host and port.isdigit() and not _listening(host, int(port)):
        # Ray itself would retry its GCS for minutes before it says so
        msg = f"--ray {address}: no Ray cluster there (nothing listens on that port)"
        raise BelvedereError(msg, hint="start one: ray start --head, or --ray auto")
    try:
        ray.init(
            address=address,
            # a cluster on a loopback address: this driver is on it too (Ray would otherwise
            # take the machine's network address for this node's and look for a raylet there)
            _node_ip_address=host if loopback else None,
            runtime_env=runtime_env,
            logging_level=logging.ERROR,
            log_to_driver=False,
            configure_logging=False,
        )
    except ConnectionError as err:
        msg = f"--ray {address}: no Ray cluster there ({err})"
        raise BelvedereError(msg, hint="start one: ray start --head, or --ray auto") from None
    results: list[R | None] = [None] * len(items)
    try:
        task: Any = ray.remote(num_cpus=1, max_retries=RAY_RETRIES, retry_exceptions=False)(_call)
        pending = {task.remote(work, item): i for i, item in enumerate(items)}
        while pending:
            done, _ = ray.wait(list(pending), num_returns=1)
            for ref in done:
                index = pending.pop(ref)
                try:
                    result = ray.get(ref)
                except ray.exceptions.RayError as err:
                    result = lost(items[index], err)
                on_done(result)
                results[index] = result
    finally:
        ray.shutdown()
    return [r for r in results if r is not None]


def _call(work: Callable[[T], R], item: T) -> R:
    """A Ray task: ``work`` (any picklable callable, a ``partial`` too) on ``item``."""
    return work(item)


def _listening(host: str, port: int) -> bool:
    try:
        with socket.create_connection((host, port), timeout=2.0):
            return True
    except OSError:
        return False


def _lost(spec: BatchSpec, run: RunDescription, err: Exception) -> Row:
    """The row of a run Ray could not finish even after its retries."""
    first = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
    row: Row = {"run": run.index, **dict(run.values)}
    row.update(status="lost", error=f"Ray: {first}", wall_s=None)
    row.update({m.name: None for m in spec.measures})
    return row
