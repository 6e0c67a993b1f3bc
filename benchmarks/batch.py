"""Runs per minute of ``belvedere batch``: one local worker (the reference, measured in the
same run), two local workers, and Ray tasks on a two-node cluster on this machine (one CPU
each, on 127.0.0.2, started here).

Each run is the kinematic mbot driven for ``--duration`` simulated seconds at ``--rtf max``,
in a process of its own. The scaling efficiency of N workers is their runs per minute over N
times one worker's (1.0: every added core does a whole core's work; the goal is >= 0.8).

    python benchmarks/batch.py [--runs 12] [--duration 20] [--no-ray]
"""

from __future__ import annotations

import argparse
import socket
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from belvedere.batch import Row, read_spec, run_local, run_ray

ROOT = Path(__file__).resolve().parents[1]
MBOT = ROOT / "examples/mbot_description/urdf/urdf/mbot_base.urdf"
RAY_HOST = "127.0.0.2"  # Ray swaps 127.0.0.1 for the machine's network address


def _spec(folder: Path, runs: int, duration: float) -> Path:
    path = folder / "spec.yaml"
    path.write_text(
        f"sim: [{MBOT}]\nduration: {duration}\nruns:\n  seed: {list(range(runs))}\n"
        '  pub: ["/cmd_vel geometry_msgs/Twist {linear: {x: 0.2}, angular: {z: 0.1}}"]\n'
        "record:\n  x: /odom pose.pose.position.x\n"
    )
    return path


def _rate(label: str, run: Callable[[], list[Row]]) -> float:
    start = time.monotonic()
    rows = run()
    minutes = (time.monotonic() - start) / 60
    failed = sum(r["status"] != "ok" for r in rows)
    if failed:
        sys.exit(f"{label}: {failed} runs failed")
    rate: float = len(rows) / minutes
    sys.stdout.write(f"{label:<28} {len(rows):3d} runs  {rate:7.1f} runs/min\n")
    return rate


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind((RAY_HOST, 0))
        port: int = sock.getsockname()[1]
    return port


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=12)
    parser.add_argument("--duration", type=float, default=20.0, help="simulated s per run")
    parser.add_argument("--no-ray", action="store_true", help="local workers only")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        spec = read_spec(_spec(Path(tmp), args.runs, args.duration))
        one = _rate("1 local worker (reference)", lambda: run_local(spec, 1, lambda _: None))
        two = _rate("2 local workers", lambda: run_local(spec, 2, lambda _: None))
        sys.stdout.write(f"2 local workers: {two / one:.2f}x one, efficiency {two / one / 2:.2f}\n")
        if args.no_ray:
            return 0
        try:
            from ray.cluster_utils import Cluster
        except ImportError:
            sys.stdout.write("Ray: not installed (pip install 'belvedere[ray]')\n")
            return 0
        head = {"num_cpus": 1, "include_dashboard": False, "node_ip_address": RAY_HOST}
        cluster = Cluster(
            initialize_head=True, head_node_args={**head, "gcs_server_port": _free_port()}
        )
        try:
            cluster.add_node(num_cpus=1, node_ip_address=RAY_HOST)
            cluster.wait_for_nodes()
            address = f"{RAY_HOST}:{cluster.address.rpartition(':')[2]}"
            on_ray = _rate("Ray, 2 nodes x 1 CPU", lambda: run_ray(spec, address, lambda _: None))
        finally:
            cluster.shutdown()  # type: ignore[no-untyped-call]  # Ray's own test helper
        sys.stdout.write(
            f"Ray (2 CPUs): {on_ray / one:.2f}x one local worker, "
            f"efficiency {on_ray / one / 2:.2f}\n"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
