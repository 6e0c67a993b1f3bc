"""A small, fast XML DOM for the files users give us, parsed safely with source positions.

Why our own: xacro's output format is defined by how ``xml.dom.minidom`` (over expat) builds
and prints trees, so we parse with the same expat and keep the same node kinds — but children
sit in a doubly linked list, so moving a node is O(1) where minidom's list insert/remove is
O(n). Every element remembers the file, line and column it came from.

Safety: a DOCTYPE may declare internal entities (expat expands them, with its built-in
amplification limits), but external entities and DTDs are never loaded, and nothing touches
the network. Elements nest at most :data:`MAX_DEPTH` deep: every reader of these trees walks
them recursively, and a deeper file stops here with an error at the element too deep, instead
of a ``RecursionError`` in whichever reader meets it first. Real files nest a few levels (a
Gazebo world about eight); a hundred levels is already no hand-written file.
"""

from __future__ import annotations

import gc
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Final
from xml.parsers import expat

from belvedere.bounded import TEXT_FILE_BYTES, LimitError, read_regular
from belvedere.errors import ParseError, SourceLocation

__all__ = [
    "MAX_DEPTH",
    "CData",
    "Comment",
    "Document",
    "Element",
    "Node",
    "ProcessingInstruction",
    "Text",
    "check_depth",
    "parse_file",
    "parse_string",
    "write_pretty",
]


MAX_DEPTH: Final = 256
"""The deepest element nesting a parsed document may have (the root is at depth 1)."""


class _Siblings:
    """The identity of one element's child list.

    Children point here instead of at their parent, so that moving *all* children of one
    element into another (what every macro expansion does) is O(1): the emptied list just
    forwards to the receiving one. ``Node.parent`` follows (and shortens) the forwarding.
    """

    __slots__ = ("forward", "owner")

    def __init__(self, owner: Element) -> None:
        self.owner = owner
        self.forward: _Siblings | None = None


class Node:
    """A node in a sibling list. Subclasses add their payload."""

    __slots__ = ("_siblings", "next", "prev")

    def __init__(self) -> None:
        self._siblings: _Siblings | None = None
        self.prev: Node | None = None
        self.next: Node | None = None

    @property
    def parent(self) -> Element | None:
        s = self._siblings
        if s is None:
            return None
        if s.forward is None:
            return s.owner
        root = s.forward
        while root.forward is not None:
            root = root.forward
        s.forward = root
        self._siblings = root
        return root.owner

    def clone(self) -> Node:
        raise NotImplementedError

    def detach(self) -> None:
        """Remove this node from its parent (no-op when it has none)."""
        parent = self.parent
        if parent is None:
            return
        if self.prev is None:
            parent.first = self.next
        else:
            self.prev.next = self.next
        if self.next is None:
            parent.last = self.prev
        else:
            self.next.prev = self.prev
        self._siblings = None
        self.prev = self.next = None


class Text(Node):
    __slots__ = ("data",)

    def __init__(self, data: str) -> None:
        # (Node's fields set here: trees have many nodes, a super() call each adds up)
        self._siblings = None
        self.prev = self.next = None
        self.data = data

    def clone(self) -> Text:
        return Text(self.data)


class CData(Node):
    __slots__ = ("data",)

    def __init__(self, data: str) -> None:
        # (Node's fields set here: trees have many nodes, a super() call each adds up)
        self._siblings = None
        self.prev = self.next = None
        self.data = data

    def clone(self) -> CData:
        return CData(self.data)


class Comment(Node):
    __slots__ = ("data", "loc")

    def __init__(self, data: str, loc: SourceLocation | None = None) -> None:
        # (Node's fields set here: trees have many nodes, a super() call each adds up)
        self._siblings = None
        self.prev = self.next = None
        self.data = data
        self.loc = loc
        """Where the comment was written (None for one made in code)."""

    def clone(self) -> Comment:
        return Comment(self.data, self.loc)


class ProcessingInstruction(Node):
    __slots__ = ("data", "target")

    def __init__(self, target: str, data: str) -> None:
        super().__init__()
        self.target = target
        self.data = data

    def clone(self) -> ProcessingInstruction:
        return ProcessingInstruction(self.target, self.data)


class Element(Node):
    """An element: qualified tag name, attributes in document order, children, origin."""

    __slots__ = ("attrs", "first", "kids", "last", "loc", "tag")

    def __init__(
        self, tag: str, attrs: dict[str, str] | None = None, loc: SourceLocation | None = None
    ) -> None:
        self._siblings = None
        self.prev = self.next = None
        self.tag = tag
        self.attrs: dict[str, str] = {} if attrs is None else attrs
        self.first: Node | None = None
        self.last: Node | None = None
        self.kids: _Siblings | None = None  # made when the first child arrives
        self.loc = loc

    def _siblings_of_children(self) -> _Siblings:
        kids = self.kids
        if kids is None:
            kids = self.kids = _Siblings(self)
        return kids

    def children(self) -> list[Node]:
        """A snapshot of the children (safe to mutate the tree while iterating it)."""
        out: list[Node] = []
        child = self.first
        while child is not None:
            out.append(child)
            child = child.next
        return out

    def elements(self) -> Iterator[Element]:
        child = self.first
        while child is not None:
            nxt = child.next
            if isinstance(child, Element):
                yield child
            child = nxt

    def first_element(self) -> Element | None:
        child = self.first
        while child is not None and not isinstance(child, Element):
            child = child.next
        return child

    def append(self, node: Node) -> None:
        node.detach()
        node._siblings = self._siblings_of_children()
        node.prev = self.last
        if self.last is None:
            self.first = node
        else:
            self.last.next = node
        self.last = node

    def insert_before(self, node: Node, ref: Node | None) -> None:
        """Insert ``node`` (detached from wherever it was) before ``ref`` (None: append)."""
        if ref is None:
            self.append(node)
            return
        if node is ref:
            return
        node.detach()
        node._siblings = self._siblings_of_children()
        node.next = ref
        node.prev = ref.prev
        if ref.prev is None:
            self.first = node
        else:
            ref.prev.next = node
        ref.prev = node

    def move_children_before(self, content: Element, ref: Node) -> None:
        """Move all children of ``content`` before ``ref`` (a child of this element), in O(1)."""
        first, last = content.first, content.last
        if first is None or last is None:
            return
        first.prev = ref.prev
        if ref.prev is None:
            self.first = first
        else:
            ref.prev.next = first
        last.next = ref
        ref.prev = last
        assert content.kids is not None  # it has children
        content.kids.forward = self._siblings_of_children()
        content.kids = None
        content.first = content.last = None

    def clone(self) -> Element:
        """A deep copy, detached, with the same source locations."""
        copy = Element(self.tag, dict(self.attrs), self.loc)
        child = self.first
        if child is None:
            return copy
        kids = copy.kids = _Siblings(copy)
        prev: Node | None = None
        while child is not None:
            c = child.clone()
            c._siblings = kids
            c.prev = prev
            if prev is None:
                copy.first = c
            else:
                prev.next = c
            prev = c
            child = child.next
        copy.last = prev
        return copy

    def text_content(self) -> str:
        parts: list[str] = []
        for node in self.children():
            if isinstance(node, Text | CData):
                parts.append(node.data)
            elif isinstance(node, Element):
                parts.append(node.text_content())
        return "".join(parts)

    def __repr__(self) -> str:
        return f"<Element {self.tag} at {self.loc}>"


class Document(Element):
    """The top of a parsed file: comments/PIs around one root element."""

    __slots__ = ("path",)

    def __init__(self, path: str) -> None:
        super().__init__("#document")
        self.path = path

    @property
    def root(self) -> Element:
        root = self.first_element()
        if root is None:  # the parser guarantees one
            msg = f"{self.path}: document has no root element"
            raise ParseError(msg)
        return root


def _too_deep(at: SourceLocation | None) -> ParseError:
    msg = f"elements nest more than {MAX_DEPTH} levels deep (the nesting limit)"
    return ParseError(msg, at, hint="no robot, world or launch file needs as many")


def check_depth(top: Element) -> None:
    """Raise the parser's nesting-limit error for a tree built in code (a xacro expansion)
    that nests deeper than :data:`MAX_DEPTH`, at the first element too deep."""
    todo = [(el, 1) for el in reversed(list(top.elements()))]
    while todo:
        el, depth = todo.pop()
        if depth > MAX_DEPTH:
            raise _too_deep(el.loc)
        todo.extend((child, depth + 1) for child in reversed(list(el.elements())))


# --- parsing -------------------------------------------------------------------------------


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


# --- writing -------------------------------------------------------------------------------

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
