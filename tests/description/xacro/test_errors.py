"""Every error names the file, line and column, says what was expected, and never crashes."""

from __future__ import annotations

from pathlib import Path

import pytest

from belvedere.description.xacro import process_file
from belvedere.errors import ParseError

HEAD = '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
TAIL = "</robot>\n"


def write(tmp_path: Path, body: str, name: str = "bad.xacro") -> Path:
    path = tmp_path / name
    path.write_text(HEAD + body + TAIL, encoding="utf-8")
    return path


def expand_error(path: Path, **kwargs: object) -> ParseError:
    with pytest.raises(ParseError) as info:
        process_file(path, **kwargs)  # type: ignore[arg-type]
    return info.value


def test_missing_include_names_the_includer(tmp_path: Path) -> None:
    path = write(tmp_path, '  <xacro:include filename="nope.xacro"/>\n')
    err = expand_error(path)
    assert str(err).startswith(f"{path}:3:3: error: cannot include ")
    assert "nope.xacro: no such file" in str(err)


def test_missing_include_in_included_file_shows_trail(tmp_path: Path) -> None:
    (tmp_path / "mid.xacro").write_text(
        HEAD + '  <xacro:include filename="gone.xacro"/>\n' + TAIL, encoding="utf-8"
    )
    path = write(tmp_path, '  <xacro:include filename="mid.xacro"/>\n')
    text = str(expand_error(path))
    assert "mid.xacro:3:3: error: cannot include" in text
    assert f"included from {path}:3:3" in text


def test_undefined_property_suggests_near_names(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        '  <xacro:property name="wheel_radius" value="1"/>\n  <a r="${wheel_radias}"/>\n',
    )
    err = expand_error(path)
    assert f"{path}:4:9: error: name 'wheel_radias' is not defined" in str(err)  # at its ${
    assert "did you mean 'wheel_radius'?" in str(err)


def test_bad_expression_shows_it_and_the_failing_part(tmp_path: Path) -> None:
    path = write(tmp_path, '  <a r="${1 +* 2}"/>\n')
    text = str(expand_error(path))
    assert f"{path}:3:14: error: invalid expression '1 +* 2'" in text
    assert "    1 +* 2\n       ^" in text


def test_unclosed_expression(tmp_path: Path) -> None:
    path = write(tmp_path, '  <a r="${1 + 2"/>\n')
    assert f"{path}:3:3: error: invalid expression: ${{1 + 2" in str(expand_error(path))


def test_runtime_error_in_expression(tmp_path: Path) -> None:
    path = write(tmp_path, '  <a r="${1/0}"/>\n')
    assert "ZeroDivisionError: division by zero when evaluating expression '1/0'" in str(
        expand_error(path)
    )


def test_unknown_macro_lists_close_names(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        '  <xacro:macro name="wheel" params="x"/>\n  <xacro:wheal x="1"/>\n',
    )
    err = expand_error(path)
    assert f"{path}:4:3: error: unknown macro name: xacro:wheal" in str(err)
    assert "did you mean xacro:wheel?" in str(err)


def test_missing_macro_parameter(tmp_path: Path) -> None:
    path = write(tmp_path, '  <xacro:macro name="m" params="a b"/>\n  <xacro:m a="1"/>\n')
    assert f"{path}:4:3: error: Undefined parameters [b] of macro 'm'" in str(expand_error(path))


def test_unknown_macro_parameter(tmp_path: Path) -> None:
    path = write(tmp_path, '  <xacro:macro name="m" params="a"/>\n  <xacro:m a="1" c="2"/>\n')
    err = expand_error(path)
    assert f"{path}:4:3: error: Invalid parameter \"c\" of macro 'm'" in str(err)
    assert "parameters: a" in str(err)


def test_missing_and_unused_blocks(tmp_path: Path) -> None:
    path = write(tmp_path, '  <xacro:macro name="m" params="*b"/>\n  <xacro:m/>\n')
    assert "Not enough blocks" in str(expand_error(path))
    path = write(tmp_path, '  <xacro:macro name="m" params=""/>\n  <xacro:m><x/></xacro:m>\n')
    assert f'{path}:4:12: error: Unused block "x"' in str(expand_error(path))


def test_circular_properties(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        '  <xacro:property name="c1" value="${c2}"/>\n'
        '  <xacro:property name="c2" value="${c1}"/>\n'
        '  <a v="${c1}"/>\n',
    )
    err = expand_error(path)
    assert "circular variable definition: c1 -> c2 -> c1" in str(err)
    assert 'lazy_eval="false"' in str(err)
    # at the property that closes the circle, with the chain of uses that led there
    assert str(err).startswith(f"{path}:4:3:")
    assert f"in property 'c2', used at {path}:3:3" in str(err)
    assert f"in property 'c1', used at {path}:5:3" in str(err)


def test_recursive_macro_without_end_is_a_clear_error(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        '  <xacro:macro name="f" params="n">\n    <xacro:f n="${n+1}"/>\n  </xacro:macro>\n'
        '  <xacro:f n="0"/>\n',
    )
    text = str(expand_error(path))
    assert "macro nesting deeper than" in text
    assert "a macro that calls itself without end?" in text
    assert f"in macro 'f' called from {path}:4:5 (" in text


def test_legitimate_deep_nesting_works(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        '  <xacro:macro name="seg" params="n">\n    <l n="${n}"/>\n'
        '    <xacro:if value="${n &lt; 500}"><xacro:seg n="${n+1}"/></xacro:if>\n'
        "  </xacro:macro>\n"
        '  <xacro:seg n="1"/>\n',
    )
    out = process_file(path)
    assert out.count("<l ") == 500


@pytest.mark.parametrize(
    ("xml", "where", "what"),
    [
        ("<robot><a></robot>", "1:13", "mismatched tag"),
        ("<robot>\n  <a x='1' x='2'/></robot>", "2:12", "duplicate attribute"),
        ("<robot><xacro:a/></robot>", "1:8", "unbound prefix"),
        ("", "1:1", "no element found"),
    ],
)
def test_malformed_xml(tmp_path: Path, xml: str, where: str, what: str) -> None:
    path = tmp_path / "bad.xacro"
    path.write_text(xml, encoding="utf-8")
    text = str(expand_error(path))
    assert text.startswith(f"{path}:{where}: error: malformed XML: {what}")


def test_non_boolean_condition(tmp_path: Path) -> None:
    path = write(tmp_path, '  <xacro:if value="1.0"><a/></xacro:if>\n')
    err = expand_error(path)
    assert f'{path}:3:3: error: Xacro conditional "1.0" evaluated to "1.0"' in str(err)


def test_arg_without_value_or_default(tmp_path: Path) -> None:
    path = write(tmp_path, '  <a v="$(arg robot_name)"/>\n')
    err = expand_error(path)
    assert f"{path}:3:3: error: undefined substitution argument 'robot_name'" in str(err)
    assert "robot_name:=VALUE" in str(err)


def test_arg_declared_without_default(tmp_path: Path) -> None:
    path = write(tmp_path, '  <xacro:arg name="x"/>\n')
    assert f"{path}:3:3: error: xacro:arg: missing attribute 'default'" in str(expand_error(path))


def test_arg_from_mappings_needs_no_default(tmp_path: Path) -> None:
    path = write(tmp_path, '  <a v="$(arg x)"/>\n')
    assert 'v="given"' in process_file(path, mappings={"x": "given"})


def test_missing_package(tmp_path: Path) -> None:
    path = write(tmp_path, '  <xacro:include filename="$(find no_such_pkg)/x.xacro"/>\n')
    text = str(expand_error(path))
    assert f"{path}:3:3: error: package 'no_such_pkg' not found; searched:" in text
    assert "--package-path" in text


def test_unknown_substitution(tmp_path: Path) -> None:
    path = write(tmp_path, '  <a v="$(bogus 1)"/>\n')
    assert "unknown substitution command $(bogus 1)" in str(expand_error(path))


def test_error_inside_macro_points_at_body_and_call(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        '  <xacro:macro name="m" params="x">\n    <link name="${x + undefined_y}"/>\n'
        "  </xacro:macro>\n"
        '  <xacro:m x="1"/>\n',
    )
    text = str(expand_error(path))
    assert text.startswith(f"{path}:4:17: error: name 'undefined_y' is not defined")
    assert f"in macro 'm' called from {path}:6:3" in text


def test_invalid_property_names(tmp_path: Path) -> None:
    path = write(tmp_path, '  <xacro:property name="1abc" value="1"/>\n')
    assert "Property names must be valid python identifiers: 1abc" in str(expand_error(path))
    path = write(tmp_path, '  <xacro:property name="__x" value="1"/>\n')
    assert "must not start with double underscore" in str(expand_error(path))


def test_errors_in_evaluated_comments_point_at_the_comment(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        '  <link name="a"/>\n  <!-- xacro:eval-comments -->\n  <!-- width ${1/0} -->\n',
    )
    text = str(expand_error(path))
    assert text.startswith(f"{path}:5:14: error: ZeroDivisionError: division by zero")
