"""The xacro tree walk: properties, macros, includes, conditionals, substitutions.

It follows xacro 2.1.1 operation by operation (including where comments go and which
whitespace nodes survive, since both show in the output) on our linked DOM, so moving nodes
costs O(1). Legacy dialects change what an unprefixed tag means and how macros are scoped.
"""

from __future__ import annotations

import gc
import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from belvedere.description.xacro._calls import MAX_MACRO_DEPTH, MacroCalls
from belvedere.description.xacro._dialects import (
    FIX_SED,
    LEGACY_KEYWORDS,
    Dialect,
    XacroWarning,
)
from belvedere.description.xacro._errors import XacroError
from belvedere.description.xacro._keywords import Keywords
from belvedere.description.xacro._macros import MacroTable
from belvedere.description.xacro._symbols import Scope, kinetic_literal, literal
from belvedere.packages import find_package_root
from belvedere.xmldom import Comment, Document, Element, Node, Text

__all__ = ["Dialect", "Processor", "XacroWarning"]


class Processor(Keywords, MacroCalls):
    """One run of xacro over one document."""

    # --- the walk ------------------------------------------------------------------------------
    def process_document(self, doc: Document, path: str | None) -> None:
        self.files = [path]
        if path is None:
            self.roots = [os.path.realpath(self.root_dir)]
        else:
            full = Path(self.root_dir, path).resolve()
            self.roots = [str(find_package_root(full) or full.parent)]
        root = doc.root
        target = root.attrs.pop("xacro:targetNamespace", None)
        if target:
            root.attrs["xmlns"] = target
        macros = MacroTable()
        scope = Scope(
            None,
            root=self.globals,
            evaluate=self.eval_property,
            typing=kinetic_literal if self.two_pass else literal,
        )
        with _expanding():
            if self.two_pass:
                self._first_pass(root, macros, scope)
            self.eval_all(root, macros, scope)

    def _first_pass(self, root: Element, macros: MacroTable, scope: Scope) -> None:
        """Kinetic's order: all includes, then every macro, then every property (even in
        false conditionals; the last definition wins), before anything is evaluated."""
        for el in _walk(root):
            if self.keyword(el) == "include":
                if "ns" in el.attrs:
                    msg = "namespaces are supported with in-order option only"
                    raise XacroError(msg, el.loc, hint="use --dialect melodic or auto")
                if "${" in el.attrs.get("filename", ""):
                    msg = "variable filename is supported with in-order option only"
                    raise XacroError(msg, el.loc, hint="use --dialect melodic or auto")
                self.current = el
                self.include(el, macros, scope, evaluate=False)
        for el in _walk(root):
            if self.keyword(el) == "macro":
                self.current = el
                self.define_macro(el, macros)
        for el in _walk(root):
            if self.keyword(el) == "property":
                self.current = el
                self.property(el, scope)

    def eval_all(self, node: Element, macros: MacroTable, scope: Scope) -> None:
        """Evaluate one element in place: attributes, then children in order."""
        attrs = node.attrs
        for name, value in list(attrs.items()):
            if name.startswith("xacro:"):
                del attrs[name]
            elif "$" in value:
                self.current = node
                try:
                    attrs[name] = self.text(self.eval_text(value, scope))
                except XacroError as err:
                    err.locate(node.loc)
                    raise
        if not self.keep_xmlns:
            attrs.pop("xmlns:xacro", None)

        child = node.first
        eval_comments = False
        while child is not None:
            nxt = child.next
            kind = type(child)
            if kind is Element:
                assert isinstance(child, Element)
                eval_comments = False
                try:
                    again = self.element(child, macros, scope)
                except XacroError as err:
                    err.locate(child.loc)
                    raise
                if again:
                    continue  # xacro:element renamed it: process it again
            elif kind is Text:
                assert isinstance(child, Text)
                data = child.data
                if "$" in data:
                    self.current = node
                    try:
                        data = child.data = self.text(self.eval_text(data, scope))
                    except XacroError as err:
                        err.locate(node.loc)
                        raise
                if eval_comments is not False and data.strip():
                    eval_comments = False
            elif kind is Comment:
                assert isinstance(child, Comment)
                if "xacro:eval-comments" in child.data:
                    eval_comments = "xacro:eval-comments:off" not in child.data
                    child.detach()
                elif eval_comments:
                    self.current = node
                    try:
                        child.data = self.text(self.eval_text(child.data, scope))
                    except XacroError as err:
                        err.locate(node.loc)
                        raise
            child = nxt

    def keyword(self, el: Element) -> str | None:
        """The xacro keyword an element is, if any (``xacro:if`` → ``if``)."""
        tag = el.tag
        if tag.startswith("xacro:"):
            return tag[6:]
        if self.legacy_tags and tag in LEGACY_KEYWORDS:
            if tag == "include" and not _is_xacro_include(el):
                return None  # Gazebo's <include><uri>…</uri></include>
            if el.loc is not None:
                self.legacy_sites.append((el.loc, tag))
            if self.dialect is Dialect.AUTO:
                self.warn_once(
                    f"tag:{tag}@{el.loc}",  # each place: -v lists what --fix rewrites
                    f"xacro tag <{tag}> without the 'xacro:' prefix: processed as ROS Melodic "
                    f"did; modern xacro copies it through. Write <xacro:{tag}>, or run "
                    "'belvedere xacro --fix FILE'",
                    el.loc,
                    legacy=tag,
                )
            else:
                self.warn_once(
                    "melodic-deprecated",
                    f"Deprecated: xacro tag '{tag}' w/o 'xacro:' xml namespace prefix "
                    f"(will be forbidden in Noetic)\nUse the following command to fix "
                    f"incorrect tag usage:\n{FIX_SED}",
                    el.loc,
                )
            return tag
        return None

    def element(self, el: Element, macros: MacroTable, scope: Scope) -> bool:
        """Process one child element; True means it was renamed and must be processed again."""
        self.current = el
        kw = self.keyword(el)
        if kw is None:  # most elements: a macro call or plain content
            if not self.macro_call(el, macros, scope):
                self.eval_all(el, macros, scope)
            return False
        if kw == "insert_block":
            self.insert_block(el, macros, scope)
        elif kw == "include":
            self.include(el, macros, scope)
        elif kw == "property":
            self.property(el, scope)
        elif kw == "macro":
            self.define_macro(el, macros)
        elif kw == "arg":
            (name, default), _ = self.attrs(el, ["name", "default"])
            if name not in self.args:
                self.args[name] = self.text(self.eval_text(default, scope))
            self.remove_previous_comments(el)
            el.detach()
        elif kw == "element" and el.tag.startswith("xacro:"):
            if "xacro:name" not in el.attrs:
                msg = "xacro:element: missing attribute 'xacro:name'"
                raise XacroError(msg)
            name = self.eval_text(el.attrs["xacro:name"], scope)
            if not name:
                msg = "xacro:element: empty name"
                raise XacroError(msg)
            del el.attrs["xacro:name"]
            el.tag = str(name)
            return True
        elif kw == "attribute" and el.tag.startswith("xacro:"):
            for required in ("name", "value"):
                if required not in el.attrs:
                    msg = f"xacro:attribute: missing attribute '{required}'"
                    raise XacroError(msg)
            name = self.eval_text(el.attrs["name"], scope)
            value = self.eval_text(el.attrs["value"], scope)
            if not name:
                msg = "xacro:attribute: empty name"
                raise XacroError(msg)
            parent = el.parent
            if isinstance(parent, Element):
                parent.attrs[str(name)] = self.text(value)
            el.detach()
        elif kw in ("if", "unless"):
            self.remove_previous_comments(el)
            (cond,), _ = self.attrs(el, ["value"])
            keep = self.boolean(self.eval_text(cond, scope), cond)
            if kw == "unless":
                keep = not keep
            if keep:
                self.eval_all(el, macros, scope)
                self.splice(el, el)
            else:
                el.detach()
        elif not self.macro_call(el, macros, scope):
            self.eval_all(el, macros, scope)
        return False


def _is_xacro_include(el: Element) -> bool:
    """Melodic's rule for an unprefixed <include>: no children, or a single text node."""
    first = el.first
    return first is None or (first.next is None and isinstance(first, Text))


def _walk(root: Element) -> Iterator[Element]:
    """Elements in document order, tolerating removal or replacement of the current one:
    after an element is replaced by content, the walk continues with that content."""
    stack: list[Node | None] = [root.first]
    while stack:
        node = stack.pop()
        if node is None:
            continue
        stack.append(node.next)
        if not isinstance(node, Element):
            continue
        prev, parent = node.prev, node.parent
        yield node
        if node.parent is parent:  # still in place: descend
            stack.append(node.first)
        else:  # removed or replaced: resume at whatever now follows its old position
            stack[-1] = prev.next if prev is not None else (parent.first if parent else None)


@contextmanager
def _expanding() -> Iterator[None]:
    """Let legitimately deep macro nesting recurse (Python frames are cheap since 3.11), and
    pause the cyclic garbage collector, whose full passes over the growing tree (parents and
    children refer to each other) would make large expansions superlinear."""
    old = sys.getrecursionlimit()
    sys.setrecursionlimit(max(old, MAX_MACRO_DEPTH * 12 + 2000))
    gc_was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if gc_was_enabled:
            gc.enable()
        sys.setrecursionlimit(old)
