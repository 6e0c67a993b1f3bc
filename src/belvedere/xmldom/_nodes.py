"""The tree: elements, text, CDATA, comments and processing instructions, each child in its
parent's doubly linked list, each element with the place in the file it came from."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Final

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
