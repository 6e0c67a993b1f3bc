"""Property-based tests: generated documents against xacro 2.1.1, and --fix against melodic."""

from __future__ import annotations

import importlib
import tempfile
import xml.dom.minidom
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from belvedere.description.xacro import Dialect, XacroError, process_file, process_string
from belvedere.description.xacro._fix import fix_file
from belvedere.description.xacro._symbols import literal

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
NAMES = ["a", "b", "c", "width", "len_x"]

numbers = st.one_of(
    st.integers(-1000, 1000).map(str),
    st.sampled_from(["0.1", "2.5", "1e3", "-0.0", "3.14159", "1e-5", "0.3"]),
)


def expressions() -> st.SearchStrategy[str]:
    leaves = st.one_of(numbers, st.sampled_from(NAMES), st.sampled_from(["pi", "True"]))

    def extend(inner: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
        binary = st.tuples(
            inner, st.sampled_from(["+", "-", "*", "/", "//", "%", "&lt;", "=="]), inner
        )
        return st.one_of(
            binary.map(lambda t: f"({t[0]} {t[1]} {t[2]})"),
            inner.map(lambda e: f"-{e}"),
            st.tuples(inner, inner).map(lambda t: f"max({t[0]}, {t[1]})"),
            st.tuples(inner, inner, inner).map(lambda t: f"({t[0]} if {t[1]} else {t[2]})"),
            inner.map(lambda e: f"round({e}, 3)"),
            inner.map(lambda e: f"python.abs({e})"),
        )

    return st.recursive(leaves, extend, max_leaves=6)


def statements() -> st.SearchStrategy[str]:
    prop = st.tuples(
        st.sampled_from(NAMES), st.one_of(numbers, expressions().map("${{{}}}".format))
    )
    return st.one_of(
        prop.map(lambda t: f'<xacro:property name="{t[0]}" value="{t[1]}"/>'),
        expressions().map(lambda e: f'<e v="${{{e}}}"/>'),
        st.tuples(numbers, expressions()).map(lambda t: f"<t>x{t[0]} ${{{t[1]}}} y</t>"),
        expressions().map(lambda e: f'<xacro:if value="${{bool({e})}}"><yes/></xacro:if>'),
        st.sampled_from(["<!-- c -->", "<plain/>", "\n  "]),
    )


def _reference(doc: str) -> str | None:
    """xacro 2.1.1 in this process; None when it rejects the document."""
    try:
        ref: Any = importlib.import_module("xacro")
    except ImportError:
        pytest.skip("xacro 2.1.1 (the reference) is not installed")
    ref.init_stacks(None)
    ref.all_includes = []
    dom = xml.dom.minidom.parseString(doc)
    try:
        ref.process_doc(dom, mappings={})
    except Exception:  # noqa: BLE001 (the reference raises anything)
        return None
    text: str = dom.toprettyxml(indent="  ")
    return text


@pytest.mark.oracle
@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(statements(), min_size=1, max_size=8))
def test_generated_documents_match_xacro_2_1_1(body: list[str]) -> None:
    doc = f'<robot name="gen" {NS}>' + "".join(body) + "</robot>"
    expected = _reference(doc)
    try:
        ours = process_string(doc, dialect=Dialect.MODERN)
    except XacroError:
        assert expected is None, f"we reject what 2.1.1 accepts:\n{doc}"
        return
    if expected is not None:
        assert ours == expected


@given(st.text(max_size=12))
def test_literal_typing_rules(text: str) -> None:
    value = literal(text)
    if len(text) >= 2 and text[0] == text[-1] == "'":
        assert value == text[1:-1]
    elif "_" in text:
        assert value == text
    elif isinstance(value, bool):
        assert text in ("true", "True", "false", "False")
    elif isinstance(value, int):
        assert value == int(text)
    elif isinstance(value, float):
        assert str(value) == str(float(text))
    else:
        assert value == text


MACRO_NAMES = ["wheel", "arm", "sensor_mount"]


@st.composite
def legacy_documents(draw: st.DrawFn) -> str:
    macros = draw(st.lists(st.sampled_from(MACRO_NAMES), min_size=1, max_size=3, unique=True))
    parts = [f'<robot name="legacy" {NS}>', '<property name="k" value="2"/>']
    for name in macros:
        keyword = draw(st.sampled_from(["macro", "xacro:macro"]))
        inner = draw(st.sampled_from(["", '<if value="${n > 1}"><big n="${n}"/></if>']))
        parts.append(
            f'<{keyword} name="{name}" params="n"><{name}_link n="${{n*k}}"/>{inner}</{keyword}>'
        )
    for _ in range(draw(st.integers(1, 5))):
        name = draw(st.sampled_from(macros))
        n = draw(st.integers(0, 3))
        parts.append(f'<{name} n="{n}"/>')
    parts.append("</robot>")
    return "\n".join(parts)


@settings(max_examples=60, deadline=None)
@given(legacy_documents())
def test_fix_then_modern_equals_melodic(doc: str) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "legacy.xacro"
        path.write_text(doc)
        legacy = process_file(path, dialect=Dialect.MELODIC).replace(f" {NS}", "")
        fix_file(path)
        assert process_file(path, dialect=Dialect.MODERN) == legacy
        assert process_file(path, dialect=Dialect.AUTO) == legacy
