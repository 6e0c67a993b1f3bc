"""``belvedere test`` against Debian's rostest (ros_comm 1.15) on the same package: the same
exit status, summary, case lines and JUnit files (their counts, cases and failure types).

Debian's rostest starts its own master on a free port, as it always does, and its nodes
serve on 127.0.0.1 (``ROS_HOSTNAME``); belvedere's runs on a graph of its own.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from tests.debian_ros import missing_debian_ros
from tests.waiting import DEADLINE

ROSTEST = Path("/usr/bin/rostest")
ROSTEST_NODES = Path("/usr/share/rostest/nodes")

pytestmark = pytest.mark.oracle

PACKAGE_XML = """<?xml version="1.0"?>
<package format="2"><name>demo</name><version>0.0.0</version>
<description>a test package</description><maintainer email="a@b.c">a</maintainer>
<license>BSD</license><buildtool_depend>catkin</buildtool_depend></package>
"""

CHECK = """#!/usr/bin/env python3
import sys, unittest
import rospy, rostest

class Check(unittest.TestCase):
    def test_ok(self):
        self.assertEqual(1, 1)

    def test_want(self):
        self.assertEqual(int(rospy.get_param("~want", 1)), 1, "want is not 1")

    def test_broken(self):
        raise KeyError("no such thing")

if __name__ == "__main__":
    rospy.init_node("check")
    rostest.rosrun("demo", "check", Check, sys.argv)
"""

TEST = """<launch>
  <param name="course" value="mbot"/>
  <test test-name="check_it" pkg="demo" type="check.py"><param name="want" value="2"/></test>
  <test test-name="param_set" pkg="rostest" type="paramtest">
    <param name="param_name_target" value="/course"/>
    <param name="param_value_expected" value="mbot"/>
  </test>
  <test test-name="gone" pkg="demo" type="nope.py"/>
</launch>
"""


@pytest.fixture
def package(tmp_path: Path) -> Path:
    why = missing_debian_ros("rospy, rostest", ROSTEST, ROSTEST_NODES)
    if why is not None:
        pytest.skip(why)
    pkg = tmp_path / "ws" / "demo"
    (pkg / "scripts").mkdir(parents=True)
    (pkg / "test").mkdir()
    (pkg / "package.xml").write_text(PACKAGE_XML)
    script = pkg / "scripts" / "check.py"
    script.write_text(CHECK)
    script.chmod(0o755)
    (pkg / "test" / "demo.test").write_text(TEST)
    return pkg


def _debian(pkg: Path, results: Path, home: Path) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "ROS_"))}
    env["PATH"] = "/usr/bin:/bin"  # Debian's python3 for the test nodes, not ours
    env["ROS_PACKAGE_PATH"] = f"{pkg.parent}:/usr/share"
    env["ROS_HOME"] = str(home)
    env["ROS_HOSTNAME"] = "127.0.0.1"
    return subprocess.run(
        [str(ROSTEST), "--results-base-dir", str(results), "demo", "demo.test"],
        env=env,
        cwd=pkg,
        capture_output=True,
        text=True,
        timeout=DEADLINE * 4,
        check=False,
    )


def _ours(pkg: Path, results: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [
            sys.executable,
            "-m",
            "belvedere",
            "test",
            "--package-path",
            str(pkg.parent),
            "--results",
            str(results),
            "demo",
            "demo.test",
        ],
        cwd=pkg,
        capture_output=True,
        text=True,
        timeout=DEADLINE * 4,
        check=False,
    )


def _report(stdout: str) -> list[str]:
    """The lines rostest's users read: case lines and the summary, colours and the traceback
    text inside failures (interpreters' paths differ) left out."""
    plain = re.sub(r"\033\[[0-9;]*m", "", stdout)
    start = plain.index("[ROSTEST]---")
    return [
        line
        for line in plain[start:].splitlines()
        if re.match(r"^(\[[^\]]+\]\[(passed|failed|FAILURE|ERROR)\]|SUMMARY| \* |ERROR:)", line)
    ]


def _shape(path: Path) -> tuple[dict[str, str], list[tuple[str, str, list[tuple[str, str]]]]]:
    """A JUnit file's counts and its cases (classname, name, [(kind, type)] of each failure
    and error)."""
    root = ET.parse(path).getroot()
    counts = {k: root.get(k, "") for k in ("tests", "failures", "errors", "name")}
    cases = [
        (
            case.get("classname", ""),
            case.get("name", ""),
            [(sub.tag, sub.get("type", "")) for sub in case if sub.tag in ("failure", "error")],
        )
        for case in root.iter("testcase")
    ]
    return counts, cases


def test_summary_exit_status_and_junit_files_are_debians(package: Path, tmp_path: Path) -> None:
    debian = _debian(package, tmp_path / "debian", tmp_path / "home")
    ours = _ours(package, tmp_path / "ours")
    assert ours.returncode == debian.returncode == 1, debian.stdout + debian.stderr
    assert _report(ours.stdout) == _report(debian.stdout), ours.stdout + "\n----\n" + debian.stdout
    for name in ("rostest-test_demo.xml", "rosunit-check_it.xml", "rosunit-param_set.xml"):
        theirs = _shape(tmp_path / "debian" / "demo" / name)
        assert _shape(tmp_path / "ours" / "demo" / name) == theirs, name


HANG = """#!/usr/bin/env python3
import rospy
rospy.init_node("hang")
rospy.spin()
"""


def test_a_test_past_its_time_limit_is_an_error_as_debians(package: Path, tmp_path: Path) -> None:
    script = package / "scripts" / "hang.py"
    script.write_text(HANG)
    script.chmod(0o755)
    (package / "test" / "demo.test").write_text(
        '<launch><test test-name="hang" pkg="demo" type="hang.py" time-limit="2"/></launch>'
    )
    debian = _debian(package, tmp_path / "debian", tmp_path / "home")
    ours = _ours(package, tmp_path / "ours")
    assert ours.returncode == debian.returncode == 1, debian.stdout + debian.stderr
    assert _report(ours.stdout) == _report(debian.stdout), ours.stdout + "\n----\n" + debian.stdout
    name = "rostest-test_demo.xml"
    theirs = _shape(tmp_path / "debian" / "demo" / name)
    assert _shape(tmp_path / "ours" / "demo" / name) == theirs
