"""Mutations of real input files, as hypothesis strategies (so failures shrink to one edit).

A mutation is a short list of edits, each drawn as plain integers and choices that index into
whatever document it meets: tree edits (drop, duplicate, move, nest an element deeply, drop an
attribute, give it a hostile value, rename a tag) on the parsed file, then text edits (delete,
insert a hostile token, duplicate a span) on its printout. ``run_bounded`` runs one example
with an alarm, so a hang fails the test instead of stalling the suite.

The CI run is small and derandomized (the same examples every run); ``scripts/fuzz.sh`` sets
``BELVEDERE_FUZZ_SCALE`` to run many more, with fresh randomness.
"""

from __future__ import annotations

import contextlib
import os
import signal
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from datetime import timedelta
from typing import Final, TypeVar

from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

from belvedere.xmldom import Document, Element, Text, parse_string, write_pretty

__all__ = [
    "HOSTILE_NUMBERS",
    "HOSTILE_TEXT",
    "HangError",
    "Mutation",
    "fuzz_settings",
    "mutations",
    "run_bounded",
    "text_mutant",
    "xml_mutant",
]

T = TypeVar("T")

SCALE: Final = int(os.environ.get("BELVEDERE_FUZZ_SCALE", "1"))
"""How many times the CI's number of examples to run (``scripts/fuzz.sh`` raises it)."""

HOSTILE_NUMBERS: Final = (
    "1e309",
    "-1e309",
    "1e308",
    "-1.7976931348623157e308",
    "9" * 400,
    "nan",
    "inf",
    "-Infinity",
    "0",
    "-0",
    "-20",
    "1e-320",
    "0x1f",
    "1_0",
    "1 2",
    " 1 ",
    "",
)
HOSTILE_TEXT: Final = (
    *HOSTILE_NUMBERS,
    "${",
    "${}",
    "${x}",
    "${1/0}",
    "$(",
    "$(arg nope)",
    "$(find nope)",
    "$(env BELVEDERE_FUZZ_NOPE)",
    "$(eval 1/0)",
    "model://" + "x" * 300,
    "package://nope/x.stl",
    "/" + "x" * 5000,
    "\u202e\u0301é\U0001f600",
    "&amp;&lt;",
    "]]>",
    "--",
    "a b",
)
"""Attribute values and text for tree edits (already-escaped where they go through XML)."""

HOSTILE_MARKUP: Final = (
    "<!DOCTYPE r [<!ENTITY a 'x'>]>",
    "<!ENTITY b 'y'>",
    "&a;",
    "&#0;",
    "&#x10FFFF;",
    "<![CDATA[",
    "]]>",
    "<!--",
    "-->",
    "<?pi x?>",
    "<a>" * 300,
    "</a>",
    "<x:y/>",
    'xmlns:x="urn:x"',
    "\x00",
    "\ufeff",
    "é",
    "${",
    "$(",
    "1e309",
    "nan",
    "9" * 400,
    '"',
    "'",
    "<",
    ">",
    "&",
)
"""Text-edit insertions: break the markup itself."""


class HangError(Exception):
    """An example ran past its time bound."""


@contextlib.contextmanager
def run_bounded(seconds: float) -> Iterator[None]:
    """Fail (HangError) if the body runs longer than ``seconds`` of wall time: a bound on a
    hang, far above what any example needs, not a measurement."""

    def expire(signum: int, frame: object) -> None:
        msg = f"one example ran over {seconds} s: a hang"
        raise HangError(msg)

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def fuzz_settings(ci_examples: int) -> Callable[[T], T]:
    """Hypothesis settings for one fuzz test: ``ci_examples`` in CI (derandomized, so the
    suite is stable), ``ci_examples * BELVEDERE_FUZZ_SCALE`` with fresh randomness when
    scaled up."""
    ci = SCALE == 1
    chosen = settings(
        max_examples=ci_examples * SCALE,
        deadline=timedelta(seconds=20),
        derandomize=ci,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    )
    # CI keeps no example database (derandomized runs need none); a long run does, so a
    # failure it finds is replayed first next time.
    return settings(chosen, database=None) if ci else chosen


@dataclass(frozen=True)
class Mutation:
    """One edit: what kind, and numbers that pick where and what (taken modulo the sizes)."""

    kind: str
    a: int
    b: int
    c: int

    def __repr__(self) -> str:
        return f"{self.kind}({self.a}, {self.b}, {self.c})"


TREE_EDITS: Final = (
    "drop-element",
    "duplicate-element",
    "move-element",
    "nest-deep",
    "drop-attribute",
    "hostile-attribute",
    "hostile-text",
    "rename-tag",
    "copy-attribute",
)
TEXT_EDITS: Final = ("delete", "insert", "duplicate-span")


def mutations(*, max_edits: int = 3) -> st.SearchStrategy[list[Mutation]]:
    """Lists of edits."""
    number = st.integers(0, 2**16)
    edit = st.builds(Mutation, st.sampled_from((*TREE_EDITS, *TEXT_EDITS)), number, number, number)
    return st.lists(edit, min_size=1, max_size=max_edits)


def xml_mutant(text: str, edits: Sequence[Mutation], tags: Sequence[str] = ()) -> str:
    """Apply edits to an XML document's text: tree edits first, then text edits. ``tags``
    are tag names a rename may pick besides the document's own (a format's keywords)."""
    doc = parse_string(text, namespaces=False)
    for edit in edits:
        if edit.kind in TREE_EDITS:
            _tree_edit(doc, edit, tags)
    out = write_pretty(doc)
    for edit in edits:
        if edit.kind in TEXT_EDITS:
            out = _text_edit(out, edit, HOSTILE_MARKUP)
    return out


def text_mutant(text: str, edits: Sequence[Mutation], tokens: Sequence[str]) -> str:
    """Apply the text edits (tree edits count as insertions), inserting ``tokens``."""
    for edit in edits:
        kind = edit.kind if edit.kind in TEXT_EDITS else "insert"
        text = _text_edit(text, Mutation(kind, edit.a, edit.b, edit.c), tokens)
    return text


def _elements(doc: Document) -> list[Element]:
    out: list[Element] = []
    todo = [doc.root]
    while todo:
        el = todo.pop()
        out.append(el)
        todo.extend(el.elements())
    return out


def _tree_edit(doc: Document, edit: Mutation, tags: Sequence[str]) -> None:
    elements = _elements(doc)
    el = elements[edit.a % len(elements)]
    parent = el.parent
    if edit.kind == "drop-element" and parent is not None and parent is not doc:
        el.detach()
    elif edit.kind == "duplicate-element" and parent is not None and parent is not doc:
        parent.insert_before(el.clone(), el.next)
    elif edit.kind == "move-element" and parent is not None and parent is not doc:
        target = elements[edit.b % len(elements)]
        inside: Element | None = target
        while inside is not None and inside is not el:
            inside = inside.parent
        if inside is None:  # not into itself
            target.append(el)
    elif edit.kind == "nest-deep":
        depth = 1 + edit.b % 320
        outer = Element(el.tag, dict(el.attrs))
        inner = outer
        for _ in range(depth):
            child = Element(el.tag, dict(el.attrs))
            inner.append(child)
            inner = child
        if parent is not None and parent is not doc:
            parent.insert_before(outer, el.next)
    elif edit.kind in ("drop-attribute", "hostile-attribute", "copy-attribute"):
        names = sorted(el.attrs)
        if edit.kind == "copy-attribute":
            donor = elements[edit.b % len(elements)]
            if donor.attrs:
                key = sorted(donor.attrs)[edit.c % len(donor.attrs)]
                el.attrs[key] = donor.attrs[key]
        elif names:
            name = names[edit.b % len(names)]
            if edit.kind == "drop-attribute":
                del el.attrs[name]
            else:
                el.attrs[name] = HOSTILE_TEXT[edit.c % len(HOSTILE_TEXT)]
    elif edit.kind == "hostile-text":
        for kid in el.children():
            if isinstance(kid, Text):
                kid.detach()
        el.append(Text(HOSTILE_TEXT[edit.b % len(HOSTILE_TEXT)]))
    elif edit.kind == "rename-tag":
        names = sorted({e.tag for e in elements} | set(tags))
        el.tag = names[edit.b % len(names)]


def _text_edit(text: str, edit: Mutation, tokens: Sequence[str]) -> str:
    at = edit.a % (len(text) + 1)
    if edit.kind == "delete":
        return text[:at] + text[at + 1 + edit.b % 16 :]
    if edit.kind == "insert":
        return text[:at] + tokens[edit.b % len(tokens)] + text[at:]
    span = text[at : at + 1 + edit.b % 200]
    return text[:at] + span + text[at:]
