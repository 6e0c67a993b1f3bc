"""Test results as rosunit keeps them: Ant JUnit XML files, written by a test node
(``rostest.rosrun``) and read back by the runner (``belvedere test``), and rosunit's summary.

The shapes are rosunit 1.15's (``junitxml.py``, ``xmlrunner.py``): a ``<testsuite>`` with
``tests``/``failures``/``errors``/``time``, one ``<testcase classname name time>`` per test
with its ``<failure type>``/``<error type>`` text, then ``<system-out>``/``<system-err>``.
Reading parses with :mod:`belvedere.xmldom` (no external entities, no network), and a file
that is missing, empty or not XML reads as no results, as rosunit's ``read`` has it.
"""

from __future__ import annotations

import io
import re
import time
import traceback
import unittest
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from types import TracebackType

from belvedere.errors import BelvedereError
from belvedere.xmldom import Element, parse_file

__all__ = [
    "CaseResult",
    "SuiteResult",
    "XmlTestResult",
    "read_results",
    "summary_text",
    "write_results",
]

_ExcInfo = tuple[type[BaseException], BaseException, TracebackType] | tuple[None, None, None]
_NOT_XML = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")
GREEN, RED, RESET = "\033[32m", "\033[1;31m", "\033[0m"


@dataclass
class CaseResult:
    """One ``<testcase>``."""

    name: str
    classname: str = ""
    time: float = 0.0
    failures: list[tuple[str, str]] = field(default_factory=list)
    """(type, text) of each ``<failure>``."""
    errors: list[tuple[str, str]] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        return not self.failures and not self.errors

    def description(self) -> str:
        """rosunit's lines for it in a summary: ``[name][passed]`` or each failure and error
        between rules."""
        if self.passed:
            return f"[{self.name}][passed]\n"
        out = []
        for kind, entries in (("FAILURE", self.failures), ("ERROR", self.errors)):
            head = f"[{self.name}][{kind}]"
            head += "-" * (80 - len(head))
            out += [f"{head}\n{text}\n" + "-" * 80 + "\n\n" for _, text in entries]
        return "".join(out)


@dataclass
class SuiteResult:
    """One ``<testsuite>``: counts as the file declares them (rosunit trusts those), cases."""

    name: str
    tests: int = 0
    failures: int = 0
    errors: int = 0
    time: float = 0.0
    cases: list[CaseResult] = field(default_factory=list)
    system_out: str = ""
    system_err: str = ""

    def accumulate(self, other: SuiteResult) -> None:
        self.tests += other.tests
        self.failures += other.failures
        self.errors += other.errors
        self.time += other.time
        self.cases += other.cases


def _clean(text: str) -> str:
    """Text an XML file can hold (rosunit escapes what it cannot)."""
    return _NOT_XML.sub(lambda m: f"&#x{ord(m.group(0)):04X};", text)


def _suite_element(suite: SuiteResult) -> ET.Element:
    top = ET.Element("testsuite")
    top.set("errors", str(suite.errors))
    top.set("failures", str(suite.failures))
    top.set("name", suite.name)
    top.set("tests", str(suite.tests))
    top.set("time", f"{suite.time:.3f}")
    for case in suite.cases:
        el = ET.SubElement(top, "testcase", classname=case.classname, name=case.name)
        el.set("time", f"{case.time:.4f}")
        for tag, entries in (("failure", case.failures), ("error", case.errors)):
            for kind, text in entries:
                ET.SubElement(el, tag, type=kind).text = _clean(text)
    ET.SubElement(top, "system-out").text = _clean(suite.system_out)
    ET.SubElement(top, "system-err").text = _clean(suite.system_err)
    return top


def write_results(path: Path, suite: SuiteResult) -> None:
    """Write ``suite`` to ``path`` (its folders made), as rosunit's XML runner does.

    Raises:
        BelvedereError: the file cannot be written.
    """
    text = ET.tostring(_suite_element(suite), encoding="unicode")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text('<?xml version="1.0" encoding="utf-8"?>\n' + text, encoding="utf-8")
    except OSError as err:
        msg = f"cannot write the test results {path}: {err.strerror}"
        raise BelvedereError(msg) from None


def _number(el: Element, name: str, kind: type[int] | type[float]) -> float:
    try:
        return kind(el.attrs.get(name) or 0)
    except ValueError:
        return 0


def read_results(path: Path, test_name: str) -> SuiteResult | None:
    """The results a test node wrote to ``path``, its cases named as rosunit names them
    (``FOLDER.FILE/case``); None if there is no file, and empty results if it is empty or
    not JUnit XML (rosunit warns and counts nothing)."""
    if not path.is_file():
        return None
    result = SuiteResult(test_name)
    try:
        doc = parse_file(path, namespaces=False, keep_blank=False)
    except BelvedereError:
        return result
    top = doc.first_element()
    suites = [top] if top is not None and top.tag == "testsuite" else []
    if top is not None and top.tag == "testsuites":
        suites = [el for el in top.elements() if el.tag == "testsuite"]
    prefix = f"{path.resolve().parent.name}.{path.name.removeprefix('TEST-').removesuffix('.xml')}"
    for suite in suites:
        result.tests += int(_number(suite, "tests", int))
        result.failures += int(_number(suite, "failures", int))
        result.errors += int(_number(suite, "errors", int))
        result.time += _number(suite, "time", float)
        for el in suite.elements():
            if el.tag != "testcase":
                continue
            classname = el.attrs.get("classname") or "unknown"
            classname = classname.partition("__main__.")[2] or classname
            case = CaseResult(f"{prefix}/{el.attrs.get('name') or 'unknown'}", classname)
            case.time = _number(el, "time", float)
            for sub in el.elements():
                text = sub.text_content().strip() or sub.attrs.get("message", "")
                if sub.tag == "failure":
                    case.failures.append((sub.attrs.get("type", ""), text))
                elif sub.tag == "error":
                    case.errors.append((sub.attrs.get("type", ""), text))
            result.cases.append(case)
    return result


def summary_text(
    runner: str,
    results: SuiteResult,
    failed_to_run: list[str],
    *,
    color: bool = True,
) -> str:
    """rosunit's ``print_runner_summary``: each case's description, ``SUMMARY``, the
    ``RESULT``, ``TESTS``/``ERRORS``/``FAILURES`` (the runner's own failures counted in),
    and which tests failed to run."""
    green, red, reset = (GREEN, RED, RESET) if color else ("", "", "")
    out = io.StringIO()
    out.write(f"[{runner}]" + "-" * 71 + "\n\n")
    for case in results.cases:
        out.write(case.description())
    for name in failed_to_run:
        out.write(f"[{name}][failed]\n")
    out.write("\nSUMMARY\n")
    if not failed_to_run and results.errors + results.failures == 0:
        out.write(f"{green} * RESULT: SUCCESS{reset}\n")
    else:
        out.write(f"{red} * RESULT: FAIL{reset}\n")
    out.write(f" * TESTS: {results.tests}\n")
    errors, failures = results.errors, results.failures + len(failed_to_run)
    out.write(f"{red} * ERRORS: {errors}{reset}\n" if errors else " * ERRORS: 0\n")
    out.write(f"{red} * FAILURES: {failures}{reset}\n" if failures else " * FAILURES: 0\n")
    if failed_to_run:
        out.write("\nERROR: The following tests failed to run:\n")
        out.writelines(f" * {name}\n" for name in failed_to_run)
    return out.getvalue()


class XmlTestResult(unittest.TestResult):
    """A unittest result that also keeps each test's outcome and time for the XML file."""

    def __init__(self) -> None:
        super().__init__()
        self.cases: list[CaseResult] = []
        self._started = 0.0

    @staticmethod
    def _case(test: unittest.TestCase) -> CaseResult:
        cls = type(test)
        name = getattr(test, "_testMethodName", str(test))
        return CaseResult(name, f"{cls.__module__}.{cls.__qualname__}")

    def startTest(self, test: unittest.TestCase) -> None:  # noqa: N802 (unittest's name)
        super().startTest(test)
        self._started = time.perf_counter()
        self.cases.append(self._case(test))

    def stopTest(self, test: unittest.TestCase) -> None:  # noqa: N802 (unittest's name)
        super().stopTest(test)
        if self.cases:
            self.cases[-1].time = time.perf_counter() - self._started

    @staticmethod
    def _kind(err: _ExcInfo) -> str:
        return "" if err[0] is None else err[0].__name__

    @staticmethod
    def _text(err: _ExcInfo) -> str:
        if err[1] is None:
            return ""
        lines = traceback.format_exception(err[1])
        return f"{err[1]}\n" + "".join(lines[1:-1])

    def _current(self, test: unittest.TestCase) -> CaseResult:
        if not self.cases or self.cases[-1].name != getattr(test, "_testMethodName", ""):
            self.cases.append(self._case(test))  # setUpClass and the like fail outside a test
        return self.cases[-1]

    def addFailure(self, test: unittest.TestCase, err: _ExcInfo) -> None:  # noqa: N802
        super().addFailure(test, err)
        self._current(test).failures.append((self._kind(err), self._text(err)))

    def addError(self, test: unittest.TestCase, err: _ExcInfo) -> None:  # noqa: N802
        super().addError(test, err)
        self._current(test).errors.append((self._kind(err), self._text(err)))

    def suite(self, name: str, elapsed: float, out: str = "", err: str = "") -> SuiteResult:
        failures, errors = len(self.failures), len(self.errors)
        return SuiteResult(
            name, self.testsRun, failures, errors, elapsed, list(self.cases), out, err
        )
