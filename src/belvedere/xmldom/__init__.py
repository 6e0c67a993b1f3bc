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

from belvedere.xmldom._nodes import (
    MAX_DEPTH,
    CData,
    Comment,
    Document,
    Element,
    Node,
    ProcessingInstruction,
    Text,
    check_depth,
)
from belvedere.xmldom._parse import parse_file, parse_string
from belvedere.xmldom._write import write_pretty

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
