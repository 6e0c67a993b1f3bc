"""How long a user's script takes from its command to ``rospy.init_node`` returning, with
Debian's ROS 1 (``python3 script.py``, real rospy) as the reference in the same run.

1. ``python3 probe.py`` with Debian's rospy: to ``import rospy`` done, and (when Debian's
   roscore is installed: this starts one) to ``init_node`` done.
2. ``belvedere run probe.py`` beside a running graph: to ``import rospy`` and ``init_node``.
3. ``import belvedere`` (which touches neither network nor disk) and ``import rospy`` as
   belvedere gives it, each in a fresh Python.

Medians of ``--runs`` runs; the ratio is belvedere's time to ``init_node`` over the
reference's (over real rospy's import alone when no roscore is here).

    python benchmarks/script_startup.py [--runs 7]
"""

from __future__ import annotations

import argparse
import os
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from belvedere.pyscripts import SITE
from debian_ros import DEBIAN_PYTHON, ROSCORE, free_port

PROBE = """\
import os, sys, time
import rospy
imported = time.time()
if os.environ.get("PROBE_INIT"):
    rospy.init_node("probe", anonymous=True)
ready = time.time()
print(imported, ready, flush=True)
os._exit(0)
"""
"""Prints when ``import rospy`` and ``init_node`` were done (wall clock, as the parent's)."""

GRAPH = """\
import sys
from belvedere.graph import Graph, ZenohTransport
g = Graph(sim_time=False, transport=ZenohTransport(endpoint=sys.argv[1]))
g.create_node("host")
g.start(rtf=None)
print("READY", flush=True)
sys.stdin.read()
g.shutdown()
"""


def timed(argv: list[str], env: dict[str, str], cwd: Path) -> tuple[float, float]:
    """Seconds from starting ``argv`` to its probe's import and ``init_node``."""
    start = time.time()
    done = subprocess.run(
        argv, env=env, cwd=cwd, capture_output=True, text=True, timeout=120, check=False
    )
    words = done.stdout.split()
    if done.returncode != 0 or len(words) != 2:
        msg = f"{' '.join(argv)} failed ({done.returncode}): {done.stderr.strip()[-500:]}"
        raise SystemExit(msg)
    imported, ready = (float(w) for w in words)
    return imported - start, ready - start


def medians(argv: list[str], env: dict[str, str], cwd: Path, runs: int) -> tuple[float, float]:
    results = [timed(argv, env, cwd) for _ in range(runs)]
    return (
        statistics.median(r[0] for r in results),
        statistics.median(r[1] for r in results),
    )


def import_cost(code: str, env: dict[str, str], runs: int) -> float:
    """Median seconds ``python -c code`` takes beyond ``python -c pass``."""

    def once(text: str) -> float:
        start = time.perf_counter()
        subprocess.run([sys.executable, "-c", text], env=env, check=True)
        return time.perf_counter() - start

    return statistics.median(once(code) - once("pass") for _ in range(runs))


def wait_for_port(port: int, seconds: float) -> bool:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=0.5):
                return True
        except OSError:
            time.sleep(0.1)
    return False


def reference(folder: Path, runs: int) -> tuple[float, float | None]:
    """Debian's rospy: (to import, to ``init_node`` or None without a roscore)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    imported, _ = medians([DEBIAN_PYTHON, "probe.py"], env, folder, runs)
    if not Path(ROSCORE).exists():
        return imported, None
    port = free_port()
    env["ROS_MASTER_URI"] = f"http://127.0.0.1:{port}"
    env["ROS_HOME"] = str(folder / "ros_home")
    core = subprocess.Popen(
        [ROSCORE, "-p", str(port)], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    try:
        if not wait_for_port(port, 30):
            return imported, None
        time.sleep(1.0)  # rosout registers after the master listens
        _, ready = medians([DEBIAN_PYTHON, "probe.py"], {**env, "PROBE_INIT": "1"}, folder, runs)
    finally:
        core.terminate()
        core.wait(30)
    return imported, ready


def belvedere_run(folder: Path, runs: int) -> tuple[float, float]:
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    env = {**os.environ, "BELVEDERE_ENDPOINT": endpoint, "PROBE_INIT": "1"}
    host = subprocess.Popen(
        [sys.executable, "-c", GRAPH, endpoint],
        env=env,
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert host.stdout is not None
        if host.stdout.readline().strip() != "READY":
            msg = "the graph did not start"
            raise SystemExit(msg)
        return medians([sys.executable, "-m", "belvedere", "run", "probe.py"], env, folder, runs)
    finally:
        assert host.stdin is not None
        host.stdin.close()
        host.wait(30)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=7)
    args = parser.parse_args()
    have_debian = (
        Path(DEBIAN_PYTHON).exists()
        and subprocess.run(
            [DEBIAN_PYTHON, "-c", "import rospy"], capture_output=True, check=False
        ).returncode
        == 0
    )
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "probe.py").write_text(PROBE)
        ours_import, ours_init = belvedere_run(folder, args.runs)
        print(f"belvedere run probe.py:  import rospy {ours_import * 1000:6.0f} ms, "
              f"init_node {ours_init * 1000:6.0f} ms")  # fmt: skip
        env = dict(os.environ)
        site_path = os.pathsep.join([str(SITE), env.get("PYTHONPATH", "")])
        bare = import_cost("import belvedere", env, args.runs)
        rospy = import_cost("import rospy", {**env, "PYTHONPATH": site_path}, args.runs)
        print(f"import belvedere {bare * 1000:6.1f} ms; belvedere's import rospy "
              f"{rospy * 1000:6.0f} ms (beyond Python's own start)")  # fmt: skip
        if not have_debian:
            print("Debian's rospy is not installed: no reference (scripts/install.sh --dev)")
            return
        ref_import, ref_init = reference(folder, args.runs)
        line = f"python3 probe.py (ROS): import rospy {ref_import * 1000:6.0f} ms"
        if ref_init is not None:
            line += f", init_node {ref_init * 1000:6.0f} ms"
        print(line)
        base = ref_init if ref_init is not None else ref_import
        what = "init_node" if ref_init is not None else "import rospy (no roscore here)"
        print(f"ratio: {ours_init / base:.2f}x ROS's time to {what}")
        shutil.rmtree(folder / "ros_home", ignore_errors=True)


if __name__ == "__main__":
    main()
