"""``belvedere test``: rostest's runner, its stock test nodes and the course's example.

Each case runs ``belvedere test`` as a user does (a process of its own, on a graph of its
own on a free port) and reads what rostest's users read: the exit status, the summary and
the JUnit files.
"""

from __future__ import annotations

import re
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from belvedere.ros1._junit import CaseResult, SuiteResult, read_results, summary_text
from tests.conftest import EXAMPLES
from tests.waiting import DEADLINE

PACKAGE_XML = """<?xml version="1.0"?>
<package format="2"><name>{name}</name><version>0.0.0</version>
<description>a test package</description><maintainer email="a@b.c">a</maintainer>
<license>BSD</license><buildtool_depend>catkin</buildtool_depend></package>
"""

CHECK = """\
import os, sys, unittest
import rospy, rostest

class Check(unittest.TestCase):
    def test_ok(self):
        self.assertEqual(1, 1)

    def test_param(self):
        self.assertEqual(rospy.get_param("~want", 1), 1, "want is not 1")

if __name__ == "__main__":
    rospy.init_node("check")
    rostest.rosrun("demo", "check", Check)
"""

HANG = """\
import rospy
rospy.init_node("hang")
rospy.spin()
"""

FLAKY = """\
import os, sys, unittest
import rospy, rostest

MARK = sys.argv[1]

class Flaky(unittest.TestCase):
    def test_second_time(self):
        first = not os.path.exists(MARK)
        open(MARK, "a").close()
        self.assertFalse(first, "the first run fails")

if __name__ == "__main__":
    rospy.init_node("flaky")
    rostest.rosrun("demo", "flaky", Flaky)
"""


def _package(root: Path, test: str, scripts: dict[str, str] | None = None) -> Path:
    """A package ``demo`` under ``root`` with ``test/demo.test`` and ``scripts/``."""
    pkg = root / "ws" / "demo"
    (pkg / "test").mkdir(parents=True, exist_ok=True)
    (pkg / "scripts").mkdir(exist_ok=True)
    (pkg / "package.xml").write_text(PACKAGE_XML.format(name="demo"))
    for name, text in (scripts or {}).items():
        script = pkg / "scripts" / name
        script.write_text("#!/usr/bin/env python3\n" + text)
        script.chmod(0o755)
    path = pkg / "test" / "demo.test"
    path.write_text(test)
    return path


def _rostest(*args: str | Path, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "belvedere", "test", *map(str, args)],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=DEADLINE * 4,
        check=False,
    )


def _summary(stdout: str) -> list[str]:
    """The summary's lines from SUMMARY on, colours taken out."""
    lines = stdout.replace("\033[32m", "").replace("\033[1;31m", "").replace("\033[0m", "")
    return lines[lines.index("SUMMARY") :].strip().splitlines()


def _suite(path: Path) -> ET.Element:
    root = ET.parse(path).getroot()
    assert root.tag == "testsuite"
    return root


def _counts(path: Path) -> tuple[int, int, int]:
    suite = _suite(path)
    return int(suite.get("tests", -1)), int(suite.get("failures", -1)), int(suite.get("errors", -1))


def test_course_example_passes_with_its_junit_files(tmp_path: Path) -> None:
    """The course's navigation in the cloister: /scan at 5.5 Hz (hztest) and a rospy node
    that sends move_base a goal through actionlib, checked from odometry."""
    proc = _rostest(
        "--package-path", EXAMPLES, "--results", tmp_path, "mbot_test", "mbot_nav.test",
        cwd=tmp_path,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "[mbot_test.rosunit-scan_rate/test_hz][passed]" in proc.stdout
    assert "[mbot_test.rosunit-reach_goal/test_reaches_goal][passed]" in proc.stdout
    assert _summary(proc.stdout) == [
        "SUMMARY",
        " * RESULT: SUCCESS",
        " * TESTS: 2",
        " * ERRORS: 0",
        " * FAILURES: 0",
    ]
    results = tmp_path / "mbot_test"
    own = _suite(results / "rostest-test_mbot_nav.xml")
    assert _counts(results / "rostest-test_mbot_nav.xml") == (2, 0, 0)
    cases = [(c.get("classname"), c.get("name")) for c in own.iter("testcase")]
    assert cases == [
        ("rostest.runner.RosTest", "testreach_goal"),
        ("rostest.runner.RosTest", "testscan_rate"),
    ]
    assert _counts(results / "rosunit-scan_rate.xml") == (1, 0, 0)
    assert _counts(results / "rosunit-reach_goal.xml") == (1, 0, 0)
    # hztest's own report of what it measured, kept in its results as rosunit keeps output
    said = _suite(results / "rosunit-scan_rate.xml").findtext("system-out") or ""
    rate = re.search(r"average rate ([0-9.]+)Hz", said)
    assert rate is not None, said
    assert float(rate.group(1)) == pytest.approx(5.5, abs=0.05)


def test_hztest_fails_a_wrong_rate(tmp_path: Path) -> None:
    test = (EXAMPLES / "mbot_test" / "test" / "mbot_laser.test").read_text()
    test = test.replace('value="5.5"', 'value="10.0"')
    path = tmp_path / "pkg" / "test" / "rate.test"
    path.parent.mkdir(parents=True)
    (tmp_path / "pkg" / "package.xml").write_text(PACKAGE_XML.format(name="rate_pkg"))
    path.write_text(test)
    proc = _rostest(path, "--package-path", EXAMPLES, "--results", tmp_path, cwd=tmp_path)
    assert proc.returncode == 2, proc.stdout + proc.stderr
    assert re.search(r"average rate \(5\.[45][0-9]*Hz\) exceeded minimum \(9\.500Hz\)", proc.stdout)
    assert _summary(proc.stdout)[1:5] == [
        " * RESULT: FAIL",
        " * TESTS: 1",
        " * ERRORS: 0",
        " * FAILURES: 1",
    ]
    assert _counts(tmp_path / "rate_pkg" / "rosunit-scan_rate.xml") == (1, 1, 0)


def test_a_failing_test_fails_with_exit_2(tmp_path: Path) -> None:
    path = _package(
        tmp_path,
        """<launch>
  <test test-name="check_it" pkg="demo" type="check.py"><param name="want" value="2"/></test>
</launch>""",
        {"check.py": CHECK},
    )
    proc = _rostest(path, "--results", tmp_path / "out", cwd=tmp_path)
    assert proc.returncode == 2, proc.stdout + proc.stderr
    assert "[demo.rosunit-check_it/test_param][FAILURE]" in proc.stdout
    assert "want is not 1" in proc.stdout
    assert "[demo.rosunit-check_it/test_ok][passed]" in proc.stdout
    assert _summary(proc.stdout) == [
        "SUMMARY",
        " * RESULT: FAIL",
        " * TESTS: 2",
        " * ERRORS: 0",
        " * FAILURES: 1",
    ]
    out = tmp_path / "out" / "demo"
    assert _counts(out / "rosunit-check_it.xml") == (2, 1, 0)
    failure = next(_suite(out / "rosunit-check_it.xml").iter("failure"))
    assert failure.get("type") == "AssertionError"
    # the runner's own file says the test ran (rostest's way: its failures are the node's)
    assert _counts(out / "rostest-test_demo.xml") == (1, 0, 0)


def test_time_limit_stops_a_hanging_test(tmp_path: Path) -> None:
    path = _package(
        tmp_path,
        '<launch><test test-name="hang" pkg="demo" type="hang.py" time-limit="2"/></launch>',
        {"hang.py": HANG},
    )
    proc = _rostest(path, "--results", tmp_path / "out", cwd=tmp_path)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert "test [hang] timed out" in proc.stderr
    assert "max time [2s] allotted for test [hang] of type [demo/hang.py]" in proc.stderr
    assert _summary(proc.stdout) == [
        "SUMMARY",
        " * RESULT: FAIL",
        " * TESTS: 0",
        " * ERRORS: 1",
        " * FAILURES: 0",
    ]
    own = _suite(tmp_path / "out" / "demo" / "rostest-test_demo.xml")
    assert (own.get("tests"), own.get("errors")) == ("1", "1")
    error = next(own.iter("error"))
    assert "max time [2s]" in (error.text or "")


@pytest.mark.parametrize(("retry", "status"), [("1", 0), ("0", 2)])
def test_retry_runs_a_failed_test_again(tmp_path: Path, retry: str, status: int) -> None:
    mark = tmp_path / "ran-once"
    path = _package(
        tmp_path,
        f'<launch><test test-name="flaky" pkg="demo" type="flaky.py" retry="{retry}" '
        f'args="{mark}"/></launch>',
        {"flaky.py": FLAKY},
    )
    proc = _rostest(path, "--results", tmp_path / "out", cwd=tmp_path)
    assert proc.returncode == status, proc.stdout + proc.stderr
    retried = "test [flaky] failed, retrying. Retries left: 0" in proc.stderr
    assert retried == (retry == "1")
    assert mark.exists()


def test_a_missing_test_node_fails_to_run_naming_its_line(tmp_path: Path) -> None:
    path = _package(
        tmp_path,
        '<launch>\n  <param name="p" value="1"/>\n'
        '  <test test-name="gone" pkg="demo" type="nope.py"/>\n</launch>\n',
    )
    proc = _rostest(path, "--results", tmp_path / "out", cwd=tmp_path)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert f"{path}:3" in proc.stderr
    assert "Test node [demo/nope.py] does not exist or is not executable" in proc.stderr
    assert "Traceback" not in proc.stderr
    assert _summary(proc.stdout)[1:] == [
        " * RESULT: FAIL",
        " * TESTS: 0",
        " * ERRORS: 0",
        " * FAILURES: 1",
        "",
        "ERROR: The following tests failed to run:",
        " * testgone",
    ]


@pytest.mark.parametrize(
    ("text", "where", "what"),
    [
        ('<launch>\n  <test test-name="t" pkg="demo" type="x.py"\n</launch>\n', ":3:", "malformed"),
        ('<launch>\n\n  <test pkg="demo" type="x.py"/>\n</launch>\n', ":3", "'test-name'"),
        (
            '<launch>\n  <test test-name="t" pkg="demo" type="x.py" time-limit="soon"/>\n</launch>',
            ":2",
            "'time-limit' must be a number: [soon]",
        ),
        (
            '<launch>\n\n\n  <test test-name="t" pkg="demo" type="x.py" args="\'open"/>\n</launch>',
            ":4",
            "cannot be split: No closing quotation",
        ),
    ],
)
def test_a_malformed_test_file_is_one_error_at_its_line(
    tmp_path: Path, text: str, where: str, what: str
) -> None:
    path = _package(tmp_path, text)
    proc = _rostest(path, cwd=tmp_path)
    assert proc.returncode == 1
    errors = [line for line in proc.stderr.splitlines() if "error:" in line]
    assert len(errors) == 1, proc.stderr
    assert f"demo.test{where}" in errors[0]
    assert what in errors[0]
    assert "Traceback" not in proc.stderr


def test_paramtest_and_publishtest(tmp_path: Path) -> None:
    """rostest's stock nodes: a parameter set (to a value), a topic that comes, one that
    does not (negative), and one expected that never comes."""
    test = (EXAMPLES / "mbot_test" / "test" / "mbot_laser.test").read_text()
    head = test[: test.index("    <!-- the laser's rate")]
    path = _package(
        tmp_path,
        head
        + """
    <param name="course" value="mbot"/>
    <test test-name="param_set" pkg="rostest" type="paramtest">
        <param name="param_name_target" value="/course"/>
        <param name="param_value_expected" value="mbot"/>
    </test>
    <test test-name="param_wrong" pkg="rostest" type="paramtest">
        <param name="param_name_target" value="/course"/>
        <param name="param_value_expected" value="turtlebot"/>
        <param name="wait_time" value="1.0"/>
    </test>
    <test test-name="published" pkg="rostest" type="publishtest">
        <rosparam>
          topics:
            - {name: /odom, timeout: 5.0}
            - {name: /nobody_publishes, timeout: 2.0, negative: true}
        </rosparam>
    </test>
    <test test-name="not_published" pkg="rostest" type="publishtest">
        <rosparam>
          topics:
            - {name: /nobody_publishes, timeout: 2.0}
        </rosparam>
    </test>
</launch>
""",
    )
    proc = _rostest(path, "--package-path", EXAMPLES, "--results", tmp_path / "out", cwd=tmp_path)
    assert proc.returncode == 2, proc.stdout + proc.stderr
    assert "[demo.rosunit-param_set/test_param][passed]" in proc.stdout
    assert "[demo.rosunit-published/test_publish][passed]" in proc.stdout
    assert "'turtlebot' != 'mbot'" in proc.stdout
    assert "Topic [/nobody_publishes] is not published" in proc.stdout
    assert _summary(proc.stdout)[1:5] == [
        " * RESULT: FAIL",
        " * TESTS: 4",
        " * ERRORS: 0",
        " * FAILURES: 2",
    ]


def _passing_and_failing(tmp_path: Path) -> tuple[Path, Path]:
    """Two .test files of one package: one whose test passes, one whose test fails."""
    passing = _package(
        tmp_path,
        '<launch><test test-name="check_it" pkg="demo" type="check.py"/></launch>',
        {"check.py": CHECK},
    )
    failing = passing.with_name("failing.test")
    failing.write_text(
        '<launch><test test-name="check_two" pkg="demo" type="check.py">'
        '<param name="want" value="2"/></test></launch>'
    )
    return passing, failing


def test_many_files_run_side_by_side(tmp_path: Path) -> None:
    passing, failing = _passing_and_failing(tmp_path)
    out = tmp_path / "out"
    proc = _rostest(passing, failing, "--workers", "2", "--results", out, cwd=tmp_path)
    assert proc.returncode == 2, proc.stdout + proc.stderr
    assert proc.stdout.index("==== test/demo.test") < proc.stdout.index("==== test/failing.test")
    assert " * RESULT: SUCCESS" in proc.stdout
    assert " * RESULT: FAIL" in proc.stdout
    assert _counts(out / "demo" / "rosunit-check_it.xml") == (2, 0, 0)
    assert _counts(out / "demo" / "rosunit-check_two.xml") == (2, 1, 0)


def test_results_files_that_are_not_junit_read_as_no_results(tmp_path: Path) -> None:
    bad = tmp_path / "rosunit-bad.xml"
    bad.write_text("<testsuite tests='3'")
    assert read_results(bad, "pkg") == SuiteResult("pkg")
    assert read_results(tmp_path / "none.xml", "pkg") is None
    entity = tmp_path / "rosunit-entity.xml"
    entity.write_text(
        '<?xml version="1.0"?><!DOCTYPE t [<!ENTITY x SYSTEM "file:///etc/passwd">]>'
        '<testsuite tests="1" failures="1"><testcase name="a"><failure>&x;</failure>'
        "</testcase></testsuite>"
    )
    read = read_results(entity, "pkg")
    assert read is not None
    assert "root:" not in str(read)


def test_summary_counts_tests_that_failed_to_run() -> None:
    results = SuiteResult("x", tests=1, cases=[CaseResult("d.rosunit-a/test_a")])
    text = summary_text("ROSTEST", results, ["testb"], color=False)
    assert text.splitlines() == [
        "[ROSTEST]" + "-" * 71,
        "",
        "[d.rosunit-a/test_a][passed]",
        "[testb][failed]",
        "",
        "SUMMARY",
        " * RESULT: FAIL",
        " * TESTS: 1",
        " * ERRORS: 0",
        " * FAILURES: 1",
        "",
        "ERROR: The following tests failed to run:",
        " * testb",
    ]


def test_many_files_on_a_ray_cluster_give_what_local_workers_give(
    cluster: str, tmp_path: Path
) -> None:
    """``--ray``: each file a Ray task, its package shipped as the task's working folder."""
    passing, failing = _passing_and_failing(tmp_path)
    outcomes = []
    for how in (["--workers", "2"], ["--ray", cluster]):
        out = tmp_path / how[0].strip("-")
        proc = _rostest(passing, failing, *how, "--results", out, cwd=tmp_path)
        assert proc.returncode == 2, proc.stdout + proc.stderr
        outcomes.append(
            [line for line in proc.stdout.splitlines() if line.startswith(("====", " * ", "["))]
        )
        assert _counts(out / "demo" / "rosunit-check_two.xml") == (2, 1, 0)
    assert outcomes[0] == outcomes[1]


def test_text_mode_prints_unittests_report_and_writes_no_files(tmp_path: Path) -> None:
    """``--text``, as rostest's: the test nodes print unittest's report and the run's
    result is not theirs (rostest warns so and exits 0 once every test ran)."""
    path = _package(
        tmp_path,
        '<launch><test test-name="check_it" pkg="demo" type="check.py">'
        '<param name="want" value="2"/></test></launch>',
        {"check.py": CHECK},
    )
    proc = _rostest(path, "--text", "--results", tmp_path / "out", cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "WARNING: overall test result is not accurate when --text is enabled" in proc.stdout
    assert "FAIL: test_param (__main__.Check.test_param)" in proc.stderr
    assert not (tmp_path / "out" / "demo" / "rosunit-check_it.xml").exists()


def test_rosrun_rostest_rostest_is_belvedere_test(tmp_path: Path) -> None:
    _package(
        tmp_path,
        '<launch><test test-name="check_it" pkg="demo" type="check.py">'
        '<param name="want" value="2"/></test></launch>',
        {"check.py": CHECK},
    )
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "belvedere",
            "run",
            "--package-path",
            str(tmp_path / "ws"),
            "rostest",
            "rostest",
            "--results",
            str(tmp_path / "out"),
            "demo",
            "demo.test",
        ],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=DEADLINE * 4,
        check=False,
    )
    assert proc.returncode == 2, proc.stdout + proc.stderr
    assert " * FAILURES: 1" in proc.stdout
