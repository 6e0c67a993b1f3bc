"""Writing the tree exactly as xacro prints it (minidom's ``toprettyxml``)."""

from __future__ import annotations

import sys
from typing import Final

from belvedere.errors import ParseError
from belvedere.xmldom._nodes import (
    CData,
    Comment,
    Document,
    Element,
    Node,
    ProcessingInstruction,
    Text,
)

__all__ = ["write_pretty"]


# xml.dom.minidom (which xacro prints with) changed in Python 3.13: it stopped escaping '"' in
# text and started escaping CR/LF/TAB in attribute values. Match the interpreter we run on, so
# our output is the reference's, byte for byte, wherever both run.
_MINIDOM_313: Final = sys.version_info >= (3, 13)


def _escape_text(s: str) -> str:
    if "&" in s:
        s = s.replace("&", "&amp;")
    if "<" in s:
        s = s.replace("<", "&lt;")
    if not _MINIDOM_313 and '"' in s:
        s = s.replace('"', "&quot;")
    if ">" in s:
        s = s.replace(">", "&gt;")
    return s


def _escape_attr(s: str) -> str:
    if "&" in s:
        s = s.replace("&", "&amp;")
    if "<" in s:
        s = s.replace("<", "&lt;")
    if '"' in s:
        s = s.replace('"', "&quot;")
    if ">" in s:
        s = s.replace(">", "&gt;")
    if _MINIDOM_313:
        s = s.replace("\r", "&#13;").replace("\n", "&#10;").replace("\t", "&#9;")
    return s


def _write_leaf(out: list[str], node: Node, indent: str) -> None:
    """Anything but an element."""
    kind = type(node)
    if kind is Text:
        assert isinstance(node, Text)
        out.append(_escape_text(indent + node.data + "\n"))
    elif kind is Comment:
        assert isinstance(node, Comment)
        if "--" in node.data or node.data.endswith("-"):
            msg = f"a comment cannot contain '--' or end in '-': {node.data!r}"
            raise ParseError(msg, node.loc, hint="XML comments end at the first '--'")
        out.append(f"{indent}<!--{node.data}-->\n")
    elif kind is CData:
        assert isinstance(node, CData)
        if "]]>" in node.data:
            msg = "']]>' is not allowed in a CDATA section"
            raise ParseError(msg)
        out.append(f"<![CDATA[{node.data}]]>")
    elif kind is ProcessingInstruction:
        assert isinstance(node, ProcessingInstruction)
        out.append(f"{indent}<?{node.target} {node.data}?>\n")


def _write_tree(out: list[str], top: Node, indent: str, step: str) -> None:
    """Write ``top`` and everything under it, with a stack of its own: output trees (a xacro
    macro that recurses) may nest deeper than Python recursion goes."""
    todo: list[tuple[Node, str] | str] = [(top, indent)]
    while todo:
        item = todo.pop()
        if isinstance(item, str):  # an end tag, or text ready to write
            out.append(item)
            continue
        el, indent = item
        if type(el) is not Element:
            _write_leaf(out, el, indent)
            continue
        assert isinstance(el, Element)
        attrs = el.attrs
        if attrs:
            parts = [indent, "<", el.tag]
            for name in sorted(attrs):
                parts.append(f' {name}="{_escape_attr(attrs[name])}"')
            out.append("".join(parts))
        else:
            out.append(f"{indent}<{el.tag}")
        first = el.first
        if first is None:
            out.append("/>\n")
            continue
        if first.next is None and type(first) is Text:
            out.append(f">{_escape_text(first.data)}</{el.tag}>\n")
            continue
        out.append(">\n")
        todo.append(f"{indent}</{el.tag}>\n")
        inner = indent + step
        child = el.last
        while child is not None:  # pushed last first, so written in order
            if type(child) is Text:
                data = child.data
                if data and not data.isspace():
                    todo.append(_escape_text(inner + data + "\n"))
            else:
                todo.append((child, inner))
            child = child.prev


def write_pretty(doc: Document | Element, *, indent: str = "  ") -> str:
    """Serialise exactly as xacro does (minidom ``toprettyxml`` with xacro's element writer)."""
    out: list[str] = []
    if isinstance(doc, Document):
        out.append('<?xml version="1.0" ?>\n')
        for node in doc.children():
            _write_tree(out, node, "", indent)
    else:
        _write_tree(out, doc, "", indent)
    return "".join(out)
