"""Modern dialect: every fixture gives 2.1.1's output byte for byte, and matches its golden file."""

from __future__ import annotations

from pathlib import Path

import pytest

from belvedere.description.xacro import Dialect, process_file
from tests.conftest import DATA, EXAMPLES, Oracle

MODERN = DATA / "xacro" / "modern"
FIXTURES = sorted(MODERN.glob("*.xacro"))
EXPECTED = MODERN / "expected"


def _ours(fixture: Path, dialect: Dialect, monkeypatch: pytest.MonkeyPatch) -> str:
    monkeypatch.chdir(fixture.parent)
    return process_file(fixture.name, dialect=dialect, mappings={})


def test_fixtures_exist() -> None:
    assert len(FIXTURES) >= 10


@pytest.mark.parametrize("fixture", FIXTURES, ids=lambda p: p.stem)
@pytest.mark.parametrize("dialect", [Dialect.AUTO, Dialect.MODERN], ids=lambda d: d.value)
def test_golden(
    fixture: Path, dialect: Dialect, monkeypatch: pytest.MonkeyPatch, update_golden: bool
) -> None:
    out = _ours(fixture, dialect, monkeypatch)
    golden = EXPECTED / f"{fixture.stem}.urdf"
    if update_golden and dialect is Dialect.MODERN:
        golden.parent.mkdir(exist_ok=True)
        golden.write_text(out, encoding="utf-8")
    assert out == golden.read_text(encoding="utf-8")


@pytest.mark.oracle
@pytest.mark.parametrize("fixture", FIXTURES, ids=lambda p: p.stem)
@pytest.mark.parametrize("dialect", [Dialect.AUTO, Dialect.MODERN], ids=lambda d: d.value)
def test_identical_to_xacro_2_1_1(
    fixture: Path, dialect: Dialect, oracle: Oracle, monkeypatch: pytest.MonkeyPatch
) -> None:
    ref = oracle.run(fixture.name, cwd=fixture.parent)
    assert ref.returncode == 0, ref.stderr
    assert _ours(fixture, dialect, monkeypatch) == ref.stdout


@pytest.mark.oracle
def test_modern_example_identical_to_xacro_2_1_1(oracle: Oracle) -> None:
    pkg = EXAMPLES / "mbot_description"
    wrapper = pkg / "urdf" / "xacro" / "gazebo" / "mbot_gazebo_modern.xacro"
    ref = oracle.run(wrapper.name, cwd=wrapper.parent, packages={"mbot_description": pkg})
    assert ref.returncode == 0, ref.stderr
    ours = process_file(wrapper, dialect=Dialect.MODERN)
    # The banner names the file as given; compare with the same spelling.
    assert ours.replace(str(wrapper), wrapper.name).splitlines()[5:] == ref.stdout.splitlines()[5:]
    assert ours.count("<link ") == 6


def test_mappings_override_arg_defaults(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(MODERN)
    out = process_file("args.xacro", mappings={"a": "0"})
    assert 'a="0"' in out
    assert "<yes/>" not in out
