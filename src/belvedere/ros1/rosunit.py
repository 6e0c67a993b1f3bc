"""``rosunit`` for the scripts belvedere runs: a unittest suite run into rosunit's JUnit XML
(``--gtest_output=xml:FILE``, or ``--text`` for unittest's own report), its file where ROS
keeps test results, and rosunit's summaries.

``unitrun`` is rosunit's entry point for a test without a graph; ``rostest.rosrun`` is the
same run inside a rostest, with the node shut down at its end.
"""

from __future__ import annotations

import contextlib
import io
import os
import sys
import time
import unittest
from collections.abc import Mapping
from pathlib import Path

from belvedere.ros1._junit import XmlTestResult, write_results

__all__ = [
    "XML_OUTPUT_FLAG",
    "print_unittest_summary",
    "results_dir",
    "run_suite",
    "unitrun",
    "xml_results_file",
]

XML_OUTPUT_FLAG = "--gtest_output=xml:"
"""The argument rostest gives a test node: where to write its results (gtest's flag)."""


def results_dir(environ: Mapping[str, str] | None = None) -> Path:
    """Where ROS keeps test results (rospkg's ``get_test_results_dir``):
    ``ROS_TEST_RESULTS_DIR``, else ``ROS_HOME/test_results``, else ``~/.ros/test_results``."""
    env = os.environ if environ is None else environ
    if env.get("ROS_TEST_RESULTS_DIR"):
        return Path(env["ROS_TEST_RESULTS_DIR"])
    home = env.get("ROS_HOME") or os.path.join(os.path.expanduser("~"), ".ros")
    return Path(home) / "test_results"


def xml_results_file(
    test_pkg: str,
    test_name: str,
    is_rostest: bool = False,
    env: Mapping[str, str] | None = None,
) -> str:
    """rosunit's name for a results file: ``DIR/PKG/rosunit-NAME.xml`` (``rostest-NAME.xml``
    for a rostest file's own), characters a file name cannot hold replaced by ``_``."""
    for char in " \"'&$!`/\\":
        test_name = test_name.replace(char, "_")
    kind = "rostest" if is_rostest else "rosunit"
    return str(results_dir(env) / test_pkg / f"{kind}-{test_name}.xml")


def print_unittest_summary(result: unittest.TestResult) -> None:
    """rosunit's summary of one unittest run, on stdout."""

    def names(entries: list[tuple[unittest.TestCase, str]]) -> str:
        return ", ".join(getattr(t, "_testMethodName", str(t)) for t, _ in entries)

    out = io.StringIO()
    out.write("-" * 61 + "\nSUMMARY:\n")
    out.write(
        "\033[32m * RESULT: SUCCESS\033[0m\n" if result.wasSuccessful() else " * RESULT: FAIL\n"
    )
    out.write(f" * TESTS: {result.testsRun}\n")
    out.write(f" * ERRORS: {len(result.errors)} [{names(result.errors)}]\n")
    out.write(f" * FAILURES: {len(result.failures)} [{names(result.failures)}]\n")
    sys.stdout.write(out.getvalue() + "\n")


def _suite(test: object) -> unittest.TestSuite:
    loader = unittest.TestLoader()
    if isinstance(test, str):
        return loader.loadTestsFromName(test)
    if isinstance(test, type) and issubclass(test, unittest.TestCase):
        return loader.loadTestsFromTestCase(test)
    if isinstance(test, unittest.TestSuite):
        return test
    if isinstance(test, unittest.TestCase):
        return unittest.TestSuite([test])
    msg = f"not a unittest test case or suite: {test!r}"
    raise TypeError(msg)


def run_suite(
    package: str, test_name: str, test: object, sysargs: list[str] | None
) -> unittest.TestResult:
    """Run ``test`` as rosunit runs it: ``--text`` prints unittest's report; otherwise the
    results go to the ``--gtest_output=xml:`` file (or rosunit's default one), what the
    tests print is kept in it, and the file is named on stdout."""
    argv = sys.argv if sysargs is None else sysargs
    result_file = None
    for arg in argv:
        if arg.startswith(XML_OUTPUT_FLAG):
            result_file = arg[len(XML_OUTPUT_FLAG) :]
    suite = _suite(test)
    if "--text" in argv:
        return unittest.TextTestRunner(verbosity=2).run(suite)
    path = Path(result_file or xml_results_file(package, os.path.basename(test_name)))
    sys.stdout.write(f"[ROSUNIT] Outputting test results to {path}\n")
    out, err = io.StringIO(), io.StringIO()
    result = XmlTestResult()
    started = time.perf_counter()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        suite.run(result)
    elapsed = time.perf_counter() - started
    suite_name = "unittest.suite.TestSuite"  # rosunit's runner names every suite so
    write_results(path, result.suite(suite_name, elapsed, out.getvalue(), err.getvalue()))
    return result


def unitrun(
    package: str,
    test_name: str,
    test: object,
    sysargs: list[str] | None = None,
    coverage_packages: list[str] | None = None,
) -> None:
    """rosunit's ``unitrun``: run the tests, print the summary, exit 1 if any failed."""
    result = run_suite(package, test_name, test, sysargs)
    print_unittest_summary(result)
    if not result.wasSuccessful():
        sys.exit(1)
