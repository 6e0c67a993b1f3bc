"""YAML files that remember where each value came from.

Configuration (rosparam files, controller YAML) is plain YAML, but a bad value must be
reported at its line. :func:`load_yaml` keeps PyYAML's node tree beside the data so any value
can be located later; a syntax error is a :class:`~belvedere.errors.ParseError` at its line.
``!degrees``/``!radians`` tags (and plain ``deg(90)``, ``rad(pi/2)``) are understood, as
``rosparam`` does.

Every YAML belvedere reads goes through :class:`Loader`, which bounds what a document can
cost: collections nest at most :data:`MAX_DEPTH` levels, and aliases may expand to at most
:data:`MAX_EXPANDED_NODES` values (a "billion laughs" bomb is refused at the alias's line
before anything is built), and an alias may not refer to the value that contains it.
"""

from __future__ import annotations

import ast
import math
import operator
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final

import yaml

from belvedere.bounded import YAML_TEXT_BYTES, LimitError, describe_size, read_regular_text
from belvedere.errors import ParseError, SourceLocation

__all__ = [
    "MAX_DEPTH",
    "MAX_EXPANDED_NODES",
    "Loader",
    "YamlDocument",
    "describe_error",
    "load_yaml",
    "load_yaml_documents",
    "load_yaml_file",
]

MAX_EXPANDED_NODES: Final = 1_000_000
"""Most values a YAML document may hold once its aliases are expanded."""


MAX_DEPTH: Final = 128
"""The deepest YAML collections may nest (PyYAML composes them recursively)."""


def _children(node: yaml.Node) -> list[yaml.Node]:
    if isinstance(node, yaml.SequenceNode):
        return list(node.value)
    if isinstance(node, yaml.MappingNode):
        return [n for pair in node.value for n in pair]
    return []


def _check_expansion(root: yaml.Node) -> None:
    """Refuse a node graph whose aliases expand to more than :data:`MAX_EXPANDED_NODES`
    values, or that contains itself: linear in the distinct nodes, before any is built."""
    size: dict[int, int] = {}
    on_path: set[int] = set()
    stack: list[tuple[yaml.Node, bool]] = [(root, False)]
    while stack:
        node, children_done = stack.pop()
        key = id(node)
        if children_done:
            on_path.discard(key)
            size[key] = total = 1 + sum(size[id(c)] for c in _children(node))
            if total > MAX_EXPANDED_NODES:
                msg = (
                    f"YAML aliases here expand to more than {MAX_EXPANDED_NODES:,} values "
                    "(an alias bomb?)"
                )
                raise yaml.composer.ComposerError(None, None, msg, node.start_mark)
            continue
        if key in size:
            continue
        if key in on_path:
            msg = "a YAML alias refers to the value that contains it (a recursive structure)"
            raise yaml.composer.ComposerError(None, None, msg, node.start_mark)
        on_path.add(key)
        stack.append((node, True))
        stack.extend((c, False) for c in _children(node) if id(c) not in size)


class Loader(yaml.SafeLoader):
    """SafeLoader plus rosparam's angle tags, a nesting limit, and YAML errors (at their
    line) for what PyYAML lets escape as Python errors."""

    def __init__(self, stream: str) -> None:
        super().__init__(stream)
        self._depth = 0

    def compose_node(self, parent: yaml.Node | None, index: int) -> yaml.Node | None:
        self._depth += 1
        try:
            if self._depth > MAX_DEPTH:
                msg = f"collections nest more than {MAX_DEPTH} levels deep (the nesting limit)"
                mark = self.peek_event().start_mark  # type: ignore[no-untyped-call]
                raise yaml.composer.ComposerError(None, None, msg, mark)
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1

    def construct_document(self, node: yaml.Node) -> Any:
        _check_expansion(node)
        return super().construct_document(node)

    def construct_object(self, node: yaml.Node, deep: bool = False) -> Any:
        """PyYAML's scalar constructors raise Python errors for values its resolver let
        through (``2001-13-45`` as a date, ``!!float x``, an int of 5000 digits)."""
        try:
            return super().construct_object(node, deep)
        except (ValueError, OverflowError) as err:
            raise yaml.constructor.ConstructorError(None, None, str(err), node.start_mark) from None
        except (KeyError, AttributeError, TypeError):
            msg = f"not a valid {node.tag.rsplit(':', 1)[-1]} value"
            raise yaml.constructor.ConstructorError(None, None, msg, node.start_mark) from None


_ARITHMETIC: Final[dict[type[ast.AST], Callable[..., float]]] = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
    ast.Pow: operator.pow,
    ast.USub: operator.neg,
    ast.UAdd: operator.pos,
}


def _arithmetic(node: ast.AST) -> float:
    """rosparam evaluates ``!radians pi/2`` with Python's ``eval``; this is the arithmetic
    of it (numbers, ``pi``, + - * / **, parentheses) without running anything else."""
    if isinstance(node, ast.Expression):
        return _arithmetic(node.body)
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
        return float(node.value)
    if isinstance(node, ast.Name) and node.id == "pi":
        return math.pi
    if isinstance(node, ast.BinOp) and type(node.op) in _ARITHMETIC:
        return float(_ARITHMETIC[type(node.op)](_arithmetic(node.left), _arithmetic(node.right)))
    if isinstance(node, ast.UnaryOp) and type(node.op) in _ARITHMETIC:
        return float(_ARITHMETIC[type(node.op)](_arithmetic(node.operand)))
    raise ValueError


def _angle(factor: float, call: str, *, expressions: bool) -> Any:
    def construct(loader: yaml.SafeLoader, node: yaml.Node) -> float:
        if not isinstance(node, yaml.ScalarNode):
            msg = f"{node.tag} needs a number, not a collection"
            raise yaml.constructor.ConstructorError(None, None, msg, node.start_mark)
        text = str(loader.construct_scalar(node)).strip()
        inner = text[len(call) + 1 : -1] if text.startswith(call + "(") else text
        try:
            if expressions:
                return _arithmetic(ast.parse(inner, mode="eval")) * factor
            return float(inner) * factor
        except (ValueError, SyntaxError, ArithmeticError, RecursionError):
            what = "an expression of numbers and pi" if expressions else "a number"
            msg = f"{node.tag} needs {what}, got {text!r}"
            raise yaml.constructor.ConstructorError(None, None, msg, node.start_mark) from None

    return construct


Loader.add_constructor("!degrees", _angle(math.pi / 180.0, "deg", expressions=False))
Loader.add_constructor("!radians", _angle(1.0, "rad", expressions=True))
# rosparam's plain ``deg(90)`` and ``rad(pi/2)``: resolved to the tags above, as its loader does
Loader.add_implicit_resolver("!degrees", re.compile(r"^deg\([^\)]*\)$"), list("d"))
Loader.add_implicit_resolver("!radians", re.compile(r"^rad\([^\)]*\)$"), list("r"))


@dataclass(frozen=True)
class YamlDocument:
    """Parsed YAML ``data`` and the means to say where any part of it was written."""

    data: Any
    path: str
    root: yaml.Node | None

    def location(self, *keys: str | int) -> SourceLocation:
        """Where the value at ``keys`` starts; the nearest enclosing value if it is absent."""
        node = self.root
        best = self._mark(node)
        for key in keys:
            child = None if node is None else self._child(node, key)
            if child is None:
                break
            node = child
            best = self._mark(node)
        return best

    def location_within(self, start: SourceLocation, *keys: str | int) -> SourceLocation:
        """Where the value at ``keys`` inside the value written at ``start`` (a line and
        column of this document, as a parameter's source gives them) starts; ``start`` when
        no value starts there, the nearest enclosing value when ``keys`` lead nowhere."""
        stack = [self.root]
        while stack:
            node = stack.pop()
            if node is None:
                continue
            here = self._mark(node)
            if (here.line, here.col) == (start.line, start.col) and not isinstance(
                node, yaml.ScalarNode
            ):
                for key in keys:
                    child = self._child(node, key)
                    if child is None:
                        break
                    node = child
                return self._mark(node)
            stack.extend(_children(node))
        return start

    @staticmethod
    def _child(node: yaml.Node, key: str | int) -> yaml.Node | None:
        if isinstance(node, yaml.MappingNode):
            pairs: list[tuple[yaml.Node, yaml.Node]] = node.value
            for key_node, value_node in pairs:
                if isinstance(key_node, yaml.ScalarNode) and key_node.value == str(key):
                    return value_node
        elif isinstance(node, yaml.SequenceNode) and isinstance(key, int):
            items: list[yaml.Node] = node.value
            return items[key] if 0 <= key < len(items) else None
        return None

    def _mark(self, node: yaml.Node | None) -> SourceLocation:
        if node is None:
            return SourceLocation(self.path)
        mark = node.start_mark
        return SourceLocation(self.path, mark.line + 1, mark.column + 1)


def describe_error(err: yaml.YAMLError, path: str) -> tuple[str, SourceLocation | None]:
    """PyYAML's error as belvedere says it: ``invalid YAML: …`` and where in ``path``."""
    mark = getattr(err, "problem_mark", None) or getattr(err, "context_mark", None)
    where = SourceLocation(path, mark.line + 1, mark.column + 1) if mark else None
    problem = getattr(err, "problem", None) or str(err)
    return f"invalid YAML: {problem}", where


def load_yaml(text: str, *, path: str = "<yaml>") -> YamlDocument:
    """Parse one YAML document; errors name ``path:line:col``. A document longer than
    :data:`~belvedere.bounded.YAML_TEXT_BYTES` (not counting the blank lines a launch file's
    inline ``<rosparam>`` is padded with to keep its line numbers) is refused unread."""
    if len(text) > YAML_TEXT_BYTES:
        size = len(text.lstrip("\n"))
        if size > YAML_TEXT_BYTES:
            msg = (
                f"the YAML is {describe_size(size)}, more than the "
                f"{describe_size(YAML_TEXT_BYTES)} belvedere reads"
            )
            raise ParseError(msg, SourceLocation(path))
    try:
        loader = Loader(text)  # PyYAML's reader checks every character here, at once
    except yaml.reader.ReaderError as err:
        at = err.position
        line, col = text.count("\n", 0, at) + 1, at - (text.rfind("\n", 0, at) + 1) + 1
        msg = f"invalid YAML: character U+{err.character:04X}: {err.reason}"
        raise ParseError(msg, SourceLocation(path, line, col)) from None
    try:
        root = loader.get_single_node()
        data = loader.construct_document(root) if root is not None else None
    except yaml.YAMLError as err:
        msg, where = describe_error(err, path)
        raise ParseError(msg, where) from None
    finally:
        loader.dispose()
    return YamlDocument(data, path, root)


def load_yaml_documents(text: str, *, path: str = "<yaml>") -> list[Any]:
    """Every document of a ``---``-separated stream (``rosparam load`` reads them all), within
    the bounds :func:`load_yaml` keeps; errors name ``path:line:col``."""
    if len(text) > YAML_TEXT_BYTES:
        msg = (
            f"the YAML is {describe_size(len(text))}, more than the "
            f"{describe_size(YAML_TEXT_BYTES)} belvedere reads"
        )
        raise ParseError(msg, SourceLocation(path))
    try:
        return list(yaml.load_all(text, Loader=Loader))
    except yaml.reader.ReaderError as err:
        msg = f"invalid YAML: character U+{err.character:04X}: {err.reason}"
        raise ParseError(msg, SourceLocation(path)) from None
    except yaml.YAMLError as err:
        msg, where = describe_error(err, path)
        raise ParseError(msg, where) from None


def load_yaml_file(path: str | Path, *, requested_at: SourceLocation | None = None) -> YamlDocument:
    """Read and parse a YAML file (a missing or unreadable file is a clear error, at
    ``requested_at`` when a file names it; only a regular file of at most
    :data:`~belvedere.bounded.YAML_TEXT_BYTES` is read)."""
    try:
        text = read_regular_text(
            path, limit=YAML_TEXT_BYTES, what="YAML file", name=repr(str(path)), at=requested_at
        )
    except LimitError as err:
        raise ParseError(err.message, err.location) from None
    return load_yaml(text, path=str(path))
