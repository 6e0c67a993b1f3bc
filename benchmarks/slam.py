"""Offline SLAM on a real log against OpenSLAM GMapping's figure on it.

Runs ``belvedere slam`` (the gmapping node's mapper) over ``aces.bag`` of the SLAM data
directory as its own process, times it (wall clock, the whole command: reading the bag,
mapping, writing the map and the trajectory), scores the trajectory with the data's own
``score.py`` (the relations metric of Kümmerle et al. 2009, run as a subprocess), and prints
ours next to GMapping's figure from the data's README, with the ratios.

    python benchmarks/slam.py --data ../shared/data/slam [--log aces] [name:=value …]

The parameters are slam_gmapping's defaults, with the resolution of the reference run
(0.05 m), and the range limits such a log asks for: its no-return readings are 50 m
(``maxRange`` just below that drops them), and beams are used for matching and mapping up to
30 m (``maxUrange``; longer ones only clear space), as is usual for a SICK LMS. The reference
run's 30 particles are not passed: the mapper keeps one trajectory, and ``particles`` has no
effect on it (setting it draws a warning).
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PARAMETERS = ("delta:=0.05", "maxRange:=49.9", "maxUrange:=30")


def _figures(text: str) -> tuple[float, float, float, float]:
    """(translation mean, its std, rotation mean, its std) from score.py's output or the
    README's GMapping row."""
    numbers = re.findall(r"(-?\d+(?:\.\d+)?)\s*(?:\+/-|±)\s*(\d+(?:\.\d+)?)", text)
    if len(numbers) < 2:
        message = f"no error figures in: {text!r}"
        raise ValueError(message)
    (t, ts), (r, rs) = numbers[:2]
    return float(t), float(ts), float(r), float(rs)


def _reference(readme: Path, log: str) -> tuple[tuple[float, float, float, float], float]:
    """GMapping's figures and wall time (s) from the README's table."""
    for line in readme.read_text().splitlines():
        if line.startswith("|") and "GMapping" in line:
            wall = re.search(r"(\d+(?:\.\d+)?)\s*s\b", line.split("|")[-2])
            if wall is None:
                message = f"{readme}: no wall time in GMapping's row"
                raise ValueError(message)
            return _figures(line), float(wall.group(1))
    message = f"{readme}: no GMapping row for {log}"
    raise ValueError(message)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", required=True, type=Path, help="the SLAM data directory")
    parser.add_argument("--log", default="aces", help="the log's name (default: aces)")
    parser.add_argument("params", nargs="*", help="more name:=value parameters")
    args = parser.parse_args()
    bag = args.data / f"{args.log}.bag"
    relations = args.data / f"{args.log}.relations"
    reference, ref_wall = _reference(args.data / "README.md", args.log)
    ref_t, _, ref_r, _ = reference
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT / "src"), env.get("PYTHONPATH")]))
    with tempfile.TemporaryDirectory() as tmp:
        traj = Path(tmp) / "trajectory.tum"
        command = [
            sys.executable,
            "-m",
            "belvedere",
            "-q",
            "slam",
            str(bag),
            "--trajectory",
            str(traj),
            "-o",
            str(Path(tmp) / "map"),
            *PARAMETERS,
            *args.params,
        ]
        started = time.perf_counter()
        subprocess.run(command, check=True, env=env)
        wall = time.perf_counter() - started
        scored = subprocess.run(
            [sys.executable, str(args.data / "score.py"), str(traj), str(relations)],
            check=True,
            capture_output=True,
            text=True,
        ).stdout
    t, ts, r, rs = _figures(scored)
    print(f"log: {args.log}   parameters: {' '.join(PARAMETERS + tuple(args.params))}")
    print(scored.strip())
    print(f"{'':14}{'translation (m)':>22}{'rotation (deg)':>20}{'wall (s)':>11}")
    for name, row in (("belvedere", (t, ts, r, rs, wall)), ("GMapping", (*reference, ref_wall))):
        a, b, c, d, e = row
        print(f"{name:14}{a:>12.4f} ± {b:<7.4f}{c:>11.3f} ± {d:<6.3f}{e:>11.1f}")
    print(f"{'ratio':14}{t / ref_t:>12.3f}{'':10}{r / ref_r:>11.3f}{'':9}{wall / ref_wall:>11.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
