"""The XML DOM's limits and writer errors: each one error at a place in the user's file."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from belvedere.cli import main
from belvedere.errors import ParseError
from belvedere.xmldom import (
    MAX_DEPTH,
    Comment,
    Element,
    parse_file,
    parse_string,
    write_pretty,
)

HEAD = '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'


def test_nesting_limit_is_an_error_at_the_first_element_too_deep() -> None:
    fits = "<a>" * MAX_DEPTH + "</a>" * MAX_DEPTH
    assert parse_string(fits).root.tag == "a"
    with pytest.raises(ParseError) as info:
        parse_string("<a>\n" + "<a>" * MAX_DEPTH + "</a>" * (MAX_DEPTH + 1), "deep.xml")
    assert info.value.describe() == (
        f"deep.xml:2:{3 * (MAX_DEPTH - 1) + 1}: error: elements nest more than 256 levels deep "
        "(the nesting limit)\n  hint: no robot, world or launch file needs as many"
    )


def test_writer_goes_deeper_than_python_recursion() -> None:
    top = Element("a")
    el = top
    for _ in range(5000):
        child = Element("a")
        el.append(child)
        el = child
    el.append(Comment(" bottom "))
    text = write_pretty(top, indent="")
    assert text.count("<a>") == 5001
    assert "<!-- bottom -->" in text


def test_comment_with_double_dash_names_where_it_was_written(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "c.xacro"
    path.write_text(
        HEAD + '  <xacro:property name="d" value="a--b"/>\n  <!-- xacro:eval-comments -->\n'
        '  <!-- value ${d} -->\n  <link name="base"/>\n</robot>\n'
    )
    out = tmp_path / "out.urdf"
    assert main(["xacro", str(path), "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert err == (
        f"{path}:4:3: error: a comment cannot contain '--' or end in '-': ' value a--b '\n"
        "  hint: XML comments end at the first '--'\n"
    )
    assert not out.exists()  # nothing half-written


def test_xacro_expansion_deeper_than_the_limit(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "rec.xacro"
    path.write_text(
        HEAD + '  <xacro:macro name="m" params="n">\n'
        '    <x><xacro:if value="${n > 0}"><xacro:m n="${n-1}"/></xacro:if></x>\n'
        "  </xacro:macro>\n"
        '  <link name="a"/>\n  <gazebo><xacro:m n="600"/></gazebo>\n</robot>\n'
    )
    # xacro writes what it expanded, however deep ...
    assert main(["xacro", str(path)]) == 0
    out = capsys.readouterr().out
    assert out.count("<x>") == 600
    assert out.count("<x/>") == 1
    # ... but a robot model that deep is the parser's nesting-limit error, at the xacro line.
    assert main(["check", str(path)]) == 1
    assert capsys.readouterr().err == (
        f"{path}:3:5: error: elements nest more than 256 levels deep (the nesting limit)\n"
        "  hint: no robot, world or launch file needs as many\n"
    )


@pytest.mark.parametrize(("make", "kind"), [("fifo", "a FIFO"), ("dir", "a directory")])
def test_parse_file_reads_only_regular_files(tmp_path: Path, make: str, kind: str) -> None:
    path = tmp_path / "robot.urdf"
    if make == "fifo":
        os.mkfifo(path)
    else:
        path.mkdir()
    with pytest.raises(ParseError, match=rf"^error: cannot read .*robot\.urdf: it is {kind}"):
        parse_file(path)
