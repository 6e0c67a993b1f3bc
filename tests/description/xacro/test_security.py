"""The sandbox: expressions reach no private names or builtins; parsing loads nothing external."""

from __future__ import annotations

import pytest

from belvedere.description.xacro import XacroError, process_string
from belvedere.errors import ParseError

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


def expand(body: str) -> str:
    return process_string(f"<robot {NS}>{body}</robot>")


@pytest.mark.parametrize(
    "expr",
    [
        "__import__('os')",
        "().__class__.__bases__",
        "[c for c in ().__class__.__mro__]",
        "(lambda: 1).__globals__",
        "python.type(1).__subclasses__()",
        "[x.__class__ for x in [1]]",
    ],
)
def test_private_names_are_refused(expr: str) -> None:
    with pytest.raises(XacroError, match=r"use of invalid name\(s\)"):
        expand(f'<a v="${{{expr}}}"/>')


@pytest.mark.parametrize("name", ["open", "eval", "exec", "compile", "getattr", "globals"])
def test_no_builtins_beyond_the_exposed_ones(name: str) -> None:
    with pytest.raises(XacroError, match=f"name '{name}' is not defined"):
        expand(f'<a v="${{{name}}}"/>')


def test_format_cannot_reach_private_attributes() -> None:
    body = (
        '<xacro:property name="fmt" value="{0._Scope__x}"/>'
        '<xacro:property name="dunder" value="{0.__class__}"/>'
    )
    with pytest.raises(XacroError, match="not allowed"):
        expand(body + '<a v="${fmt.format(xacro)}"/>')
    with pytest.raises(XacroError, match="not allowed"):
        expand(body + '<a v="${dunder.format(1)}"/>')
    assert 'v="7-x"' in expand('<xacro:property name="f" value="{0}-x"/><a v="${f.format(7)}"/>')


def test_eval_substitution_refuses_double_underscores() -> None:
    with pytest.raises(XacroError, match="double underscore"):
        expand('<a v="$(eval __import__)"/>')


def test_external_entities_are_never_loaded(tmp_path: object) -> None:
    doc = (
        '<?xml version="1.0"?><!DOCTYPE r [<!ENTITY x SYSTEM "file:///etc/passwd">]>'
        f"<robot {NS}><a>&x;</a></robot>"
    )
    with pytest.raises(ParseError):
        process_string(doc)


def test_dtd_with_system_id_is_refused() -> None:
    doc = f'<!DOCTYPE robot SYSTEM "http://example.com/r.dtd"><robot {NS}/>'
    with pytest.raises(ParseError, match="external DTDs are not loaded"):
        process_string(doc)


def test_entity_expansion_bombs_are_refused() -> None:
    bomb = (
        '<?xml version="1.0"?><!DOCTYPE r [<!ENTITY a "aaaaaaaaaa">'
        '<!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">]>'
        f"<robot {NS}>&b;</robot>"
    )
    with pytest.raises(ParseError):
        process_string(bomb)
