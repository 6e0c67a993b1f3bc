"""YAML files that remember where each value came from.

Configuration (rosparam files, controller YAML) is plain YAML, but a bad value must be
reported at its line. :func:`load_yaml` keeps PyYAML's node tree beside the data so any value
can be located later; a syntax error is a :class:`~belvedere.errors.ParseError` at its line.
``!degrees``/``!radians`` tags are understood, as ``rosparam`` does.

Aliases are bounded: a document whose aliases would expand to more than
:data:`MAX_EXPANDED_NODES` values (a "billion laughs" bomb), or an alias that refers to the
value containing it, is refused before anything is built.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final

import yaml

from belvedere.errors import ParseError, SourceLocation

__all__ = ["MAX_EXPANDED_NODES", "YamlDocument", "check_expansion", "load_yaml", "load_yaml_file"]

MAX_EXPANDED_NODES: Final = 1_000_000
"""Most values a YAML document may hold once its aliases are expanded."""


def _children(node: yaml.Node) -> list[yaml.Node]:
    if isinstance(node, yaml.SequenceNode):
        return list(node.value)
    if isinstance(node, yaml.MappingNode):
        return [n for pair in node.value for n in pair]
    return []


def check_expansion(root: yaml.Node | None, path: str) -> None:
    """Refuse a node graph whose aliases expand to more than :data:`MAX_EXPANDED_NODES`
    values, or that contains itself. Linear in the number of distinct nodes."""
    if root is None:
        return
    size: dict[int, int] = {}
    on_path: set[int] = set()
    stack: list[tuple[yaml.Node, bool]] = [(root, False)]
    while stack:
        node, children_done = stack.pop()
        key = id(node)
        if children_done:
            on_path.discard(key)
            total = 1 + sum(size[id(c)] for c in _children(node))
            size[key] = total
            if total > MAX_EXPANDED_NODES:
                mark = node.start_mark
                msg = (
                    f"YAML aliases here expand to more than {MAX_EXPANDED_NODES:,} values "
                    "(an alias bomb?)"
                )
                raise ParseError(msg, SourceLocation(path, mark.line + 1, mark.column + 1))
            continue
        if key in size:
            continue
        if key in on_path:
            mark = node.start_mark
            msg = "a YAML alias refers to the value that contains it (a recursive structure)"
            raise ParseError(msg, SourceLocation(path, mark.line + 1, mark.column + 1))
        on_path.add(key)
        stack.append((node, True))
        stack.extend((c, False) for c in _children(node) if id(c) not in size)


class _Loader(yaml.SafeLoader):
    """SafeLoader plus rosparam's angle tags."""


def _angle(factor: float) -> Any:
    def construct(loader: yaml.SafeLoader, node: yaml.Node) -> float:
        assert isinstance(node, yaml.ScalarNode)
        text = str(loader.construct_scalar(node))
        try:
            return float(text) * factor
        except ValueError:
            msg = f"{node.tag} needs a number, got {text!r}"
            raise yaml.constructor.ConstructorError(None, None, msg, node.start_mark) from None

    return construct


_Loader.add_constructor("!degrees", _angle(math.pi / 180.0))
_Loader.add_constructor("!radians", _angle(1.0))


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
            child: yaml.Node | None = None
            if isinstance(node, yaml.MappingNode):
                for key_node, value_node in node.value:
                    if isinstance(key_node, yaml.ScalarNode) and key_node.value == str(key):
                        child = value_node
                        break
            elif (
                isinstance(node, yaml.SequenceNode)
                and isinstance(key, int)
                and 0 <= key < len(node.value)
            ):
                child = node.value[key]
            if child is None:
                break
            node = child
            best = self._mark(node)
        return best

    def _mark(self, node: yaml.Node | None) -> SourceLocation:
        if node is None:
            return SourceLocation(self.path)
        mark = node.start_mark
        return SourceLocation(self.path, mark.line + 1, mark.column + 1)


def load_yaml(text: str, *, path: str = "<yaml>") -> YamlDocument:
    """Parse one YAML document; errors name ``path:line:col``."""
    loader = _Loader(text)
    try:
        root = loader.get_single_node()
        check_expansion(root, path)
        data = loader.construct_document(root) if root is not None else None
    except RecursionError:
        msg = "invalid YAML: nested too deeply"
        raise ParseError(msg, SourceLocation(path)) from None
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None) or getattr(err, "context_mark", None)
        where = SourceLocation(path, mark.line + 1, mark.column + 1) if mark else None
        problem = getattr(err, "problem", None) or str(err)
        msg = f"invalid YAML: {problem}"
        raise ParseError(msg, where) from None
    finally:
        loader.dispose()
    return YamlDocument(data, path, root)


def load_yaml_file(path: str | Path) -> YamlDocument:
    """Read and parse a YAML file (a missing or unreadable file is a clear error)."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as err:
        msg = f"cannot read YAML file {str(path)!r}: {getattr(err, 'strerror', None) or err}"
        raise ParseError(msg) from None
    return load_yaml(text, path=str(path))
