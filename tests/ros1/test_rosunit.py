"""``rosunit`` and ``rostest`` as scripts import them: a unittest run into rosunit's JUnit
XML, read back as the runner reads it, and where results files go."""

from __future__ import annotations

import io
import unittest
import xml.etree.ElementTree as ET
from contextlib import redirect_stdout
from pathlib import Path

import pytest

from belvedere.ros1 import rosunit
from belvedere.ros1._junit import read_results


class _Sample(unittest.TestCase):
    __test__ = False  # run by the tests below, not by pytest

    def test_passes(self) -> None:
        print("said while testing")  # noqa: T201 (kept in <system-out>, as rosunit keeps it)

    def test_fails(self) -> None:
        assert 1 + 1 == 3, "one is not two"

    def test_raises(self) -> None:
        msg = "missing"
        raise KeyError(msg)


def test_a_run_is_written_as_rosunit_writes_it_and_read_back(tmp_path: Path) -> None:
    path = tmp_path / "out" / "rosunit-sample.xml"
    with redirect_stdout(io.StringIO()) as said:
        result = rosunit.run_suite("pkg", "sample", _Sample, ["x", f"--gtest_output=xml:{path}"])
    assert f"[ROSUNIT] Outputting test results to {path}" in said.getvalue()
    assert (result.testsRun, len(result.failures), len(result.errors)) == (3, 1, 1)
    root = ET.parse(path).getroot()
    assert (root.tag, root.get("name")) == ("testsuite", "unittest.suite.TestSuite")
    assert (root.get("tests"), root.get("failures"), root.get("errors")) == ("3", "1", "1")
    cases = {c.get("name"): c for c in root.iter("testcase")}
    assert set(cases) == {"test_passes", "test_fails", "test_raises"}
    assert {c.get("classname") for c in cases.values()} == {f"{__name__}._Sample"}
    failure = cases["test_fails"].find("failure")
    assert failure is not None
    assert failure.get("type") == "AssertionError"
    assert "one is not two" in (failure.text or "")
    error = cases["test_raises"].find("error")
    assert error is not None
    assert error.get("type") == "KeyError"
    assert "said while testing" in (root.findtext("system-out") or "")

    read = read_results(path, "pkg")
    assert read is not None
    assert (read.tests, read.failures, read.errors) == (3, 1, 1)
    names = sorted(c.name for c in read.cases)
    assert names == [
        f"out.rosunit-sample/{n}" for n in ("test_fails", "test_passes", "test_raises")
    ]
    assert [c.passed for c in read.cases if c.name.endswith("test_passes")] == [True]


def test_results_go_where_ros_keeps_them(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.delenv("ROS_TEST_RESULTS_DIR", raising=False)
    monkeypatch.setenv("ROS_HOME", str(tmp_path / "home"))
    assert rosunit.xml_results_file("pkg", "a b/c") == str(
        tmp_path / "home" / "test_results" / "pkg" / "rosunit-a_b_c.xml"
    )
    monkeypatch.setenv("ROS_TEST_RESULTS_DIR", str(tmp_path / "results"))
    assert rosunit.xml_results_file("pkg", "demo", is_rostest=True) == str(
        tmp_path / "results" / "pkg" / "rostest-demo.xml"
    )


def test_unitrun_exits_1_when_a_test_failed(tmp_path: Path) -> None:
    with redirect_stdout(io.StringIO()) as said, pytest.raises(SystemExit) as ended:
        rosunit.unitrun("pkg", "sample", _Sample, [f"--gtest_output=xml:{tmp_path / 'r.xml'}"])
    assert ended.value.code == 1
    assert " * RESULT: FAIL" in said.getvalue()
    assert " * FAILURES: 1 [test_fails]" in said.getvalue()
    assert " * ERRORS: 1 [test_raises]" in said.getvalue()
