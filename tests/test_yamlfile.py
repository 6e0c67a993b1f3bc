"""YAML that remembers where its values were written."""

from __future__ import annotations

import math
import os
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from belvedere.bounded import YAML_TEXT_BYTES
from belvedere.errors import ParseError, SourceLocation
from belvedere.yamlfile import load_yaml, load_yaml_file


def test_locations_of_values_and_fallbacks() -> None:
    doc = load_yaml("a:\n  b: 1\n  c: [1, 2]\nd: !degrees 90\n", path="x.yaml")
    assert doc.data == {"a": {"b": 1, "c": [1, 2]}, "d": pytest.approx(math.pi / 2)}
    assert str(doc.location("a", "c", 1)) == "x.yaml:3:10"
    assert str(doc.location("a", "missing")) == "x.yaml:2:3"  # the enclosing mapping
    assert str(doc.location()) == "x.yaml:1:1"
    assert load_yaml("").data is None


@pytest.mark.parametrize(
    ("text", "where"),
    [
        ("a: [1,\nb: 2\n", "bad.yaml:3:1"),
        ("a: 1\n  b: 2\n", "bad.yaml:2:4"),
        ("a: !radians x\n", "bad.yaml:1:4"),
        ("a: 1\na: *nothing\n", "bad.yaml:2:4"),
    ],
)
def test_errors_name_file_line_and_column(text: str, where: str) -> None:
    with pytest.raises(ParseError, match=f"^{where}: error: invalid YAML"):
        load_yaml(text, path="bad.yaml")


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(ParseError, match="cannot read YAML file"):
        load_yaml_file(tmp_path / "none.yaml")


def test_a_fifo_is_refused_where_it_is_asked_for(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "gains.yaml")
    at = SourceLocation("robot.launch", 4, 3)
    with pytest.raises(
        ParseError, match=r"^robot\.launch:4:3: error: cannot read YAML file .*: it is a FIFO"
    ):
        load_yaml_file(tmp_path / "gains.yaml", requested_at=at)


def test_text_that_is_not_utf8_is_refused_at_its_byte(tmp_path: Path) -> None:
    (tmp_path / "a.yaml").write_bytes(b"a: 1\nbb: \xe9t\xe9\n")
    with pytest.raises(ParseError, match=r"a\.yaml:2:5: error: .*not UTF-8 text \(byte 0xe9\)"):
        load_yaml_file(tmp_path / "a.yaml")


def test_yaml_past_the_cap_is_refused_unread(tmp_path: Path) -> None:
    big = "a: 1\n" + "#" * YAML_TEXT_BYTES
    with pytest.raises(ParseError, match=r"^big\.yaml: error: the YAML is 4\.0 MiB, more than"):
        load_yaml(big, path="big.yaml")
    (tmp_path / "big.yaml").write_text(big)
    with pytest.raises(ParseError, match=r"it is 4\.0 MiB, more than the 4 MiB belvedere reads"):
        load_yaml_file(tmp_path / "big.yaml")
    # the blank lines an inline <rosparam> is padded with (to keep its lines) do not count
    assert load_yaml("\n" * YAML_TEXT_BYTES + "a: 1\n").data == {"a": 1}


@given(st.dictionaries(st.from_regex(r"k_[a-z]{1,8}", fullmatch=True), st.integers(), min_size=1))
def test_every_key_is_located_on_its_own_line(data: dict[str, int]) -> None:
    # (keys start with k_ so YAML 1.1 does not read 'no' or 'on' as booleans)
    text = "".join(f"{k}: {v}\n" for k, v in data.items())
    doc = load_yaml(text)
    assert doc.data == data
    for line, key in enumerate(data, start=1):
        assert doc.location(key).line == line


def test_a_character_yaml_does_not_allow_is_an_error_at_its_place() -> None:
    with pytest.raises(
        ParseError,
        match=r"^x\.yaml:2:4: error: invalid YAML: character U\+0000: special characters are "
        "not allowed$",
    ):
        load_yaml("a: 1\nb: \x00\n", path="x.yaml")


def test_rosparam_angles_deg_rad_and_pi_expressions() -> None:
    data = load_yaml("a: !radians pi/2\nb: deg(180)\nc: rad(-pi)\nd: !degrees 90\ne: degx\n").data
    assert data == {"a": math.pi / 2, "b": math.pi, "c": -math.pi, "d": math.pi / 2, "e": "degx"}
    with pytest.raises(ParseError, match="numbers and pi"):
        load_yaml("a: !radians __import__('os')\n")
