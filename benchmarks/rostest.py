"""Wall time of ``belvedere test`` against Debian's rostest (the reference, measured in the same
run) on one package: a rospy unittest node and rostest's ``paramtest``, each test with its
launch brought up fresh, as rostest does. Then files per minute for many copies of the
course's example (``examples/mbot_test/test/mbot_nav.test``: the laser mbot in MuJoCo in the
cloister, hztest on /scan, a rospy node sending move_base a goal) with one and two local
workers.

    python benchmarks/rostest.py [--repeat 3] [--files 4]
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
ROSTEST = Path("/usr/bin/rostest")

PACKAGE_XML = """<?xml version="1.0"?>
<package format="2"><name>bench</name><version>0.0.0</version><description>b</description>
<maintainer email="a@b.c">a</maintainer><license>BSD</license>
<buildtool_depend>catkin</buildtool_depend></package>
"""
CHECK = """#!/usr/bin/env python3
import sys, unittest
import rospy, rostest

class Check(unittest.TestCase):
    def test_param(self):
        self.assertEqual(rospy.get_param("/course"), "mbot")

if __name__ == "__main__":
    rospy.init_node("check")
    rostest.rosrun("bench", "check", Check, sys.argv)
"""
TEST = """<launch>
  <param name="course" value="mbot"/>
  <test test-name="check_it" pkg="bench" type="check.py"/>
  <test test-name="param_set" pkg="rostest" type="paramtest">
    <param name="param_name_target" value="/course"/>
  </test>
</launch>
"""


def _package(folder: Path) -> Path:
    pkg = folder / "ws" / "bench"
    (pkg / "scripts").mkdir(parents=True)
    (pkg / "test").mkdir()
    (pkg / "package.xml").write_text(PACKAGE_XML)
    script = pkg / "scripts" / "check.py"
    script.write_text(CHECK)
    script.chmod(0o755)
    (pkg / "test" / "bench.test").write_text(TEST)
    return pkg


def _timed(argv: list[str], *, env: dict[str, str] | None = None, cwd: Path) -> float:
    start = time.monotonic()
    proc = subprocess.run(argv, env=env, cwd=cwd, capture_output=True, text=True, check=False)
    wall = time.monotonic() - start
    if proc.returncode != 0:
        sys.stderr.write(proc.stdout + proc.stderr)
        msg = f"{argv[0]} failed ({proc.returncode})"
        raise SystemExit(msg)
    return wall


def _debian_env(pkg: Path, home: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "ROS_"))}
    env.update(
        PATH="/usr/bin:/bin",
        ROS_PACKAGE_PATH=f"{pkg.parent}:/usr/share",
        ROS_HOME=str(home),
        ROS_HOSTNAME="127.0.0.1",
    )
    return env


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--files", type=int, default=4)
    options = parser.parse_args()
    belvedere = [sys.executable, "-m", "belvedere", "test", "-q"]
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        pkg = _package(folder)
        if ROSTEST.exists():
            theirs = min(
                _timed(
                    [str(ROSTEST), "--results-base-dir", str(folder / "r"), "bench", "bench.test"],
                    env=_debian_env(pkg, folder / "home"),
                    cwd=pkg,
                )
                for _ in range(options.repeat)
            )
            ours = min(
                _timed(
                    [
                        *belvedere,
                        "--package-path",
                        str(pkg.parent),
                        "--results",
                        str(folder / "o"),
                        "bench",
                        "bench.test",
                    ],
                    cwd=pkg,
                )
                for _ in range(options.repeat)
            )
            print(f"Debian rostest (reference): {theirs:.2f} s")
            print(f"belvedere test:             {ours:.2f} s")
            print(f"speed-up: {theirs / ours:.2f}x")
        else:
            print(f"{ROSTEST} is not installed: no reference run")
        # many copies of the course's example, one and two at a time
        package = folder / "examples" / "mbot_test"
        shutil.copytree(EXAMPLES / "mbot_test", package)
        example = package / "test" / "mbot_nav.test"
        copies = [example.with_name(f"copy_{i}.test") for i in range(options.files)]
        for copy in copies:
            shutil.copy(example, copy)
        rates = {}
        for workers in (1, 2):
            wall = _timed(
                [
                    *belvedere,
                    "--package-path",
                    str(EXAMPLES),
                    "--workers",
                    str(workers),
                    "--results",
                    str(folder / f"w{workers}"),
                    *map(str, copies),
                ],
                cwd=folder,
            )
            rates[workers] = options.files / wall * 60
            print(f"{workers} worker(s): {rates[workers]:.1f} files/min")
        print(f"scaling efficiency of 2 workers: {rates[2] / (2 * rates[1]):.2f}")


if __name__ == "__main__":
    main()
