"""Parsing with expat into the tree, as minidom's builder does: safely (no external entity or
DTD is ever loaded) and with source positions."""

from __future__ import annotations

import gc
from pathlib import Path
from xml.parsers import expat

from belvedere.bounded import TEXT_FILE_BYTES, LimitError, read_regular
from belvedere.errors import ParseError, SourceLocation
from belvedere.xmldom._nodes import (
    MAX_DEPTH,
    CData,
    Comment,
    Document,
    Element,
    Node,
    ProcessingInstruction,
    Text,
    _too_deep,
)

__all__ = ["parse_file", "parse_string"]


class _Builder:
    """Builds our DOM from expat events the way minidom's namespace-aware builder does."""

    def __init__(self, path: str, *, namespaces: bool, keep_blank: bool = True) -> None:
        self.path = path
        self.keep_blank = keep_blank
        self.doc = Document(path)
        self.cur: Element = self.doc
        self.in_cdata = False
        self.cdata_continue = False
        self.parser = expat.ParserCreate(namespace_separator=" " if namespaces else None)
        p = self.parser
        if namespaces:
            p.namespace_prefixes = True
        p.buffer_text = True
        p.ordered_attributes = True
        p.SetParamEntityParsing(expat.XML_PARAM_ENTITY_PARSING_NEVER)
        p.StartElementHandler = self.start if namespaces else self.start_plain
        p.EndElementHandler = self.end
        p.CharacterDataHandler = self.chars
        p.CommentHandler = self.comment
        p.ProcessingInstructionHandler = self.pi
        p.StartCdataSectionHandler = self.start_cdata
        p.EndCdataSectionHandler = self.end_cdata
        p.StartNamespaceDeclHandler = self.ns_decl
        p.ExternalEntityRefHandler = self.external_entity
        p.EntityDeclHandler = self.entity_decl
        p.StartDoctypeDeclHandler = self.doctype
        self.pending_ns: list[tuple[str, str]] = []
        self.in_dtd = False
        self.depth = 0

    def loc(self) -> SourceLocation:
        return SourceLocation(
            self.path, self.parser.CurrentLineNumber, self.parser.CurrentColumnNumber + 1
        )

    @staticmethod
    def qname(name: str) -> str:
        if " " not in name:
            return name
        parts = name.split(" ")
        if len(parts) == 3:
            return f"{parts[2]}:{parts[1]}"
        return parts[1]

    def ns_decl(self, prefix: str | None, uri: str | None) -> None:
        self.pending_ns.append((prefix or "", uri or ""))

    def start(self, name: str, attributes: list[str]) -> None:
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise _too_deep(self.loc())
        attrs: dict[str, str] = {}
        if self.pending_ns:
            for prefix, uri in self.pending_ns:
                attrs[f"xmlns:{prefix}" if prefix else "xmlns"] = uri
            self.pending_ns.clear()
        qname = self.qname
        for i in range(0, len(attributes), 2):
            attrs[qname(attributes[i])] = attributes[i + 1]
        p = self.parser
        el = Element(
            qname(name),
            attrs,
            SourceLocation(self.path, p.CurrentLineNumber, p.CurrentColumnNumber + 1),
        )
        self._add(el)
        self.cur = el

    def start_plain(self, name: str, attributes: list[str]) -> None:
        """``start`` without namespace processing (names arrive as written)."""
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise _too_deep(self.loc())
        p = self.parser
        el = Element(
            name,
            dict(zip(attributes[::2], attributes[1::2], strict=True)) if attributes else {},
            SourceLocation(self.path, p.CurrentLineNumber, p.CurrentColumnNumber + 1),
        )
        self._add(el)
        self.cur = el

    def _add(self, node: Node) -> None:
        """Append a new node to the current element (cheaper than ``append``)."""
        cur = self.cur
        node._siblings = cur._siblings_of_children()
        last = cur.last
        node.prev = last
        if last is None:
            cur.first = node
        else:
            last.next = node
        cur.last = node

    def end(self, name: str) -> None:
        self.depth -= 1
        parent = self.cur.parent
        self.cur = parent if parent is not None else self.doc

    def chars(self, data: str) -> None:
        last = self.cur.last
        if self.in_cdata:
            if self.cdata_continue and type(last) is CData:
                last.data += data
                return
            self._add(CData(data))
            self.cdata_continue = True
        elif type(last) is Text:
            last.data += data
        elif self.keep_blank or not data.isspace():
            self._add(Text(data))

    def start_cdata(self) -> None:
        self.in_cdata = True
        self.cdata_continue = False

    def end_cdata(self) -> None:
        self.in_cdata = False
        self.cdata_continue = False

    def comment(self, data: str) -> None:
        if not self.in_dtd:
            self._add(Comment(data, self.loc()))

    def pi(self, target: str, data: str) -> None:
        if not self.in_dtd:
            self._add(ProcessingInstruction(target, data))

    def doctype(self, name: str, sysid: str | None, pubid: str | None, internal: bool) -> None:
        if sysid or pubid:
            msg = "external DTDs are not loaded: remove the SYSTEM/PUBLIC identifier"
            raise ParseError(msg, self.loc())
        msg = f"DOCTYPE declarations are not supported (<!DOCTYPE {name} …>)"
        raise ParseError(msg, self.loc(), hint="robot and world files need no DOCTYPE")

    def entity_decl(self, name: str, *args: object) -> None:
        msg = f"entity declarations are not supported (entity {name!r})"
        raise ParseError(msg, self.loc())

    def external_entity(self, *args: object) -> int:
        msg = "external entities are never loaded"
        raise ParseError(msg, self.loc())


def parse_string(
    text: str | bytes,
    path: str = "<string>",
    *,
    namespaces: bool = True,
    keep_blank: bool = True,
) -> Document:
    """Parse XML text; ``path`` names it in source locations and errors.

    With ``namespaces`` (xacro's way) undeclared prefixes are errors; without, ``a:b`` is just a
    name (TinyXML's way, which urdfdom uses). Without ``keep_blank``, whitespace-only text
    between elements is dropped (data formats need none of it)."""
    builder = _Builder(path, namespaces=namespaces, keep_blank=keep_blank)
    gc_was_enabled = gc.isenabled()
    gc.disable()  # the tree is one big cycle (parent <-> child): collecting mid-build is waste
    try:
        builder.parser.Parse(text, True)
    except expat.ExpatError as err:
        where = SourceLocation(path, err.lineno, err.offset + 1)
        reason = expat.ErrorString(err.code)
        msg = f"malformed XML: {reason}"
        raise ParseError(msg, where) from None
    finally:
        if gc_was_enabled:
            gc.enable()
    if builder.doc.first_element() is None:
        msg = "no root element"
        raise ParseError(msg, SourceLocation(path))
    return builder.doc


def parse_file(
    path: str | Path,
    display: str | None = None,
    *,
    namespaces: bool = True,
    keep_blank: bool = True,
) -> Document:
    """Parse an XML file. ``display`` is the name used in locations (default: ``path``).

    Only a regular file of at most :data:`~belvedere.bounded.TEXT_FILE_BYTES` is read (a FIFO
    or a device is refused, not waited on): ``cannot read robot.urdf: it is a FIFO…``."""
    name = display if display is not None else str(path)
    try:
        data = read_regular(path, limit=TEXT_FILE_BYTES, what="", name=name)
    except LimitError as err:
        raise ParseError(err.message, err.location) from None
    return parse_string(data, name, namespaces=namespaces, keep_blank=keep_blank)
