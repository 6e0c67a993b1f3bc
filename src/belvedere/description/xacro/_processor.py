"""The xacro tree walk: properties, macros, includes, conditionals, substitutions.

It follows xacro 2.1.1 operation by operation (including where comments go and which
whitespace nodes survive, since both show in the output) on our linked DOM, so moving nodes
costs O(1). Legacy dialects change what an unprefixed tag means and how macros are scoped.
"""

from __future__ import annotations

import gc
import glob
import keyword
import logging
import os
import re
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from belvedere.bounded import YAML_TEXT_BYTES, LimitError, read_regular_text
from belvedere.description.xacro._builtins import to_yaml_value
from belvedere.description.xacro._calls import MAX_MACRO_DEPTH, MacroCalls
from belvedere.description.xacro._dialects import (
    FIX_SED,
    LEGACY_KEYWORDS,
    Dialect,
    XacroWarning,
)
from belvedere.description.xacro._errors import XacroError
from belvedere.description.xacro._expr import EXPR
from belvedere.description.xacro._interpreter import Compiled, ExpressionError, evaluate
from belvedere.description.xacro._macros import Macro, MacroTable, parse_macro_params
from belvedere.description.xacro._substitutions import Substitutions
from belvedere.description.xacro._symbols import (
    NameSpace,
    Scope,
    boolean,
    kinetic_boolean,
    kinetic_literal,
    literal,
    make_global_symbols,
)
from belvedere.description.xacro._text import Part, program, programs, python2_str
from belvedere.errors import ParseError, SourceLocation, did_you_mean, pinpoint
from belvedere.packages import PackageIndex, find_package_root
from belvedere.xmldom import Comment, Document, Element, Node, Text, parse_file

__all__ = ["Dialect", "Processor", "XacroWarning"]

logger = logging.getLogger("belvedere.xacro")


def _is_valid_name(name: str) -> bool:
    return name.isidentifier() and not keyword.iskeyword(name)


class _MissingIncludeError(XacroError):
    """An include whose file does not exist (skipped when the include is optional)."""


class Processor(MacroCalls):
    """One run of xacro over one document."""

    def __init__(
        self,
        *,
        mappings: dict[str, str] | None = None,
        dialect: Dialect = Dialect.AUTO,
        packages: PackageIndex | None = None,
        root_dir: str | None = None,
        warn: Callable[[XacroWarning], None] | None = None,
        python2_floats: bool = False,
        strict: bool = False,
    ) -> None:
        self.args: dict[str, str] = dict(mappings or {})
        self.dialect = dialect
        self.text: Callable[[Any], str] = python2_str if python2_floats else str
        """How values become text (ROS 1 under Python 2 printed floats with 12 digits)."""
        self.strict = strict
        """Refuse to read files outside the model's package roots (else: a warning)."""
        self.roots: list[str] = []
        """The model's own package (or directory), as real paths; packages found are added."""
        self.legacy_tags = dialect is not Dialect.MODERN
        self.two_pass = dialect is Dialect.KINETIC
        self.boolean = kinetic_boolean if self.two_pass else boolean
        self.keep_xmlns = dialect in (Dialect.MELODIC, Dialect.KINETIC)
        """ROS 1 xacro left the xmlns:xacro declaration in its output."""
        self.packages = packages if packages is not None else PackageIndex([])
        self.root_dir = root_dir or os.curdir
        self.files: list[str | None] = []
        self.calls: list[tuple[Macro, SourceLocation | None]] = []
        self.includes: list[str] = []
        self.warnings: list[XacroWarning] = []
        self.legacy_sites: list[tuple[SourceLocation, str]] = []
        self.macro_names: set[str] = set()
        """Every name a macro was ever given (a quick test before scoped lookups)."""
        self.nested_definitions: dict[str, str] = {}
        """Macros defined inside another macro's expansion (name -> enclosing macro)."""
        """Unprefixed tags treated as xacro (for --fix): where, and the tag."""
        self._warn_sink = warn
        self._warned: set[str] = set()
        self.marker = Text("\n\n")
        """xacro moves one shared blank text node around to stop comment removal; so do we."""
        self.current: Element | None = None
        self.origin: SourceLocation | None = None
        """Where the lazy property being evaluated was defined (errors point there)."""
        self.substitute = Substitutions(
            args=self.args,
            packages=self.packages,
            root_dir=self.root_dir,
            current_file=lambda: self.files[-1] if self.files else None,
            here=self.here,
        )
        self.globals = make_global_symbols(
            warn=self.warn,
            xacro_functions={
                "load_yaml": self.load_yaml,
                "abs_filename": self.abs_filename,
                "dotify": to_yaml_value,
                "arg": lambda name: self.args[name],
                "message": self._message("message"),
                "warning": self._message("warning"),
                "error": self._message("error"),
                "print_location": self._message("print_location"),
                "fatal": self._fatal,
            },
        )

    # --- diagnostics -------------------------------------------------------------------------
    def here(self) -> SourceLocation | None:
        return self.current.loc if self.current is not None else None

    def warn(
        self, message: str, location: SourceLocation | None = None, *, legacy: str | None = None
    ) -> None:
        w = XacroWarning(message, location or self.here(), legacy)
        self.warnings.append(w)
        if self._warn_sink is not None:
            self._warn_sink(w)
        elif legacy is not None:
            logger.debug("%s", w)  # one summary line stands for them all (expand_file)
        else:
            logger.warning("%s", w)

    def warn_once(
        self,
        key: str,
        message: str,
        location: SourceLocation | None = None,
        *,
        legacy: str | None = None,
    ) -> None:
        if key not in self._warned:
            self._warned.add(key)
            self.warn(message, location, legacy=legacy)

    def _message(self, kind: str) -> Callable[..., str]:
        def emit(*args: Any, **kwargs: Any) -> str:
            text = " ".join(str(a) for a in args)
            if kind == "message":
                logger.info("%s", text)
            elif kind == "print_location":
                logger.info("%s", self.trail_text())
            else:
                self.warn(f"{kind}: {text}" if kind == "error" else text)
            return ""

        return emit

    def _fatal(self, *args: Any) -> str:
        raise XacroError(" ".join(str(a) for a in args))

    def trail_text(self) -> str:
        lines = [f"when processing {self.here() or self.files[-1] or '<string>'}"]
        for macro, at in reversed(self.calls):
            lines.append(f"  in macro '{macro.name}' called from {at}")
        return "\n".join(lines)

    # --- files ---------------------------------------------------------------------------------
    def abs_filename(self, spec: str) -> str:
        if os.path.isabs(spec):
            return spec
        parent = self.files[-1] if self.files else None
        base = os.path.dirname(parent) if parent else "."
        return os.path.join(base, spec)

    def check_readable(self, path: str, at: SourceLocation | None) -> None:
        """Warn (or, when strict, refuse) when a model reads a file outside every package
        root it resolved: xacro reads absolute paths, but a downloaded robot that reads
        ``/etc/passwd`` or ``~/.ssh`` should not do so silently."""
        real = os.path.realpath(os.path.join(self.root_dir, path))
        roots = [*self.roots, *(os.path.realpath(r) for r in self.substitute.found)]
        if any(real == r or real.startswith(r.rstrip(os.sep) + os.sep) for r in roots):
            return
        where = ", ".join(dict.fromkeys(roots)) or "none"
        path = os.path.normpath(path)
        if self.strict:
            msg = f"refusing to read {path}: it is outside the model's package roots ({where})"
            raise XacroError(msg, at, hint="without --strict it is read, with a warning")
        self.warn_once(
            "outside:" + real,
            f"reads {path}, outside the model's package roots ({where}); xacro reads it too "
            "(--strict refuses)",
            at,
        )

    def load_yaml(self, filename: str) -> Any:
        path = self.abs_filename(filename)
        self.check_readable(path, self.origin or self.here())
        self.includes.append(path)
        try:
            text = read_regular_text(
                os.path.join(self.root_dir, path),
                limit=YAML_TEXT_BYTES,
                what="YAML file",
                name=path,
            )
        except LimitError as err:
            msg = err.message.replace("cannot read", "cannot load", 1)
            here = self.origin or self.here()
            error = XacroError(msg, err.location if err.location and err.location.line else None)
            if error.location is not None and here is not None:
                error.add_trail("loaded by xacro.load_yaml at", here)
            raise error from None
        from belvedere.description.xacro._yaml import parse_yaml  # PyYAML loads only if used

        unit_scope = Scope(None, root=self.globals, evaluate=self.eval_property)
        try:
            return parse_yaml(text, path=path, unit_scope=unit_scope)
        except XacroError as err:
            here = self.origin or self.here()
            if err.location is not None and here is not None:
                err.add_trail("loaded by xacro.load_yaml at", here)
            raise

    # --- text evaluation -----------------------------------------------------------------------
    def eval_text(self, text: str, scope: Scope) -> Any:
        """Evaluate ``${}``/``$()`` in ``text``: one token keeps its type, more join as text."""
        if "$" not in text:
            return text
        parts = programs.get(text)
        if parts is None:
            parts = program(text)
        if len(parts) == 1:
            return self._eval_part(parts[0], scope)
        to_text = self.text
        return "".join([p if type(p) is str else to_text(self._eval_part(p, scope)) for p in parts])

    def eval_property(
        self, text: str, scope: Scope, name: str, where: SourceLocation | None
    ) -> Any:
        """Evaluate a lazy property on its first use: errors point at its definition."""
        outer = self.origin
        self.origin = where
        try:
            return self.eval_text(text, scope)
        except XacroError as err:
            err.locate(where)
            used = outer or self.here()
            if used is not None and used != where:
                err.add_trail(f"in property '{name}', used at", used)
            raise
        finally:
            self.origin = outer

    def _eval_part(self, part: Part, scope: Scope) -> Any:
        if type(part) is Compiled:
            try:
                return evaluate(part, scope)
            except ExpressionError as err:
                self._expression_failed(err, part.expr, scope)
                raise
        if isinstance(part, str):
            return part
        assert isinstance(part, tuple)
        kind, payload = part
        if kind == EXPR:  # with a $() inside, or not compilable: evaluated as xacro does
            expr = payload if "$" not in payload else str(self.eval_text(payload, scope))
            try:
                return evaluate(expr, scope)
            except ExpressionError as err:
                self._expression_failed(err, payload, scope)
                raise
        inner = str(self.eval_text(payload, scope)) if "$" in payload else payload
        return self.substitute(inner)

    def _expression_failed(self, err: ExpressionError, payload: str, scope: Scope) -> None:
        """Add what helps to an expression's error: near names, its place in the file."""
        name = getattr(err.cause, "name", None)
        if isinstance(err.cause, NameError) and name:
            err.hint = _did_you_mean(name, scope)
        if err.location is None:  # the construct's column, else the '${' itself
            offset = 0 if err.offset is None else 2 + err.offset
            err.locate(pinpoint(self.origin or self.here(), "${" + payload + "}", offset))

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

    def attrs(
        self, el: Element, required: list[str], optional: tuple[str, ...] | list[str] = ()
    ) -> tuple[list[str], list[str | None]]:
        """Required and optional attributes of a xacro tag; warns about unknown ones."""
        values: list[str] = []
        for name in required:
            if name not in el.attrs:
                msg = f"{el.tag}: missing attribute '{name}'"
                raise XacroError(msg, el.loc)
            values.append(el.attrs[name])
        allowed = {*required, *optional}
        extra = [a for a in el.attrs if a not in allowed and not a.startswith("xmlns:")]
        if extra:
            self.warn(f"{el.tag}: unknown attribute(s): {', '.join(extra)}", el.loc)
        return values, [el.attrs.get(name) for name in optional]

    # --- structure helpers ---------------------------------------------------------------------
    def remove_previous_comments(self, node: Node) -> None:
        """Drop the comments right before a xacro tag (at most one newline between)."""
        nxt = node.next
        prev = node.prev
        parent = node.parent
        while prev is not None:
            if isinstance(prev, Text) and prev.data.isspace() and prev.data.count("\n") <= 1:
                prev = prev.prev
            if prev is not None and type(prev) is Comment:
                comment = prev
                prev = prev.prev
                comment.detach()
            else:
                if nxt is not None and nxt is not self.marker and parent is not None:
                    parent.insert_before(self.marker, nxt)
                return

    @staticmethod
    def splice(node: Node, content: Element) -> None:
        """Replace ``node`` by the children of ``content`` (moved, not copied)."""
        _move_children(content, node)
        node.detach()

    def import_namespaces(self, parent: Node | None, attrs: dict[str, str]) -> None:
        """Lift ``xmlns:*`` declarations of an expanded root onto its new parent."""
        if not isinstance(parent, Element):
            return
        for name, value in attrs.items():
            if name.startswith("xmlns:"):
                old = parent.attrs.get(name)
                if old is not None and old != value:
                    self.warn(
                        f"inconsistent namespace redefinitions for {name}:\n"
                        f" old: {old}\n new: {value} ({self.files[-1]})"
                    )
                else:
                    parent.attrs[name] = value

    # --- keywords ----------------------------------------------------------------------------
    def insert_block(self, el: Element, macros: MacroTable, scope: Scope) -> None:
        (name,), _ = self.attrs(el, ["name"])
        if "**" + name in scope:
            block = scope["**" + name]
            content_only = True
        elif "*" + name in scope:
            block = scope["*" + name]
            content_only = False
        else:
            msg = f'Undefined block "{name}"'
            raise XacroError(msg, el.loc)
        block = block.clone()
        self.eval_all(block, macros, scope)
        if content_only:
            self.splice(el, block)
        else:
            parent = el.parent
            assert parent is not None
            parent.insert_before(block, el)
            el.detach()

    def property(self, el: Element, scope: Scope) -> None:
        self.remove_previous_comments(el)
        (name_t,), (value, default, remove_t, scope_kind, lazy_t) = self.attrs(
            el, ["name"], ["value", "default", "remove", "scope", "lazy_eval"]
        )
        name = self.eval_text(name_t, scope)
        if not isinstance(name, str) or not _is_valid_name(name):
            msg = f"Property names must be valid python identifiers: {name}"
            raise XacroError(msg, el.loc)
        if name.startswith("__"):
            msg = f"Property names must not start with double underscore: {name}"
            raise XacroError(msg, el.loc)
        remove = self.boolean(self.eval_text(remove_t or "false", scope), remove_t)
        if sum([value is not None, default is not None, remove]) > 1:
            msg = f"Property attributes default, value, and remove are mutually exclusive: {name}"
            raise XacroError(msg, el.loc)
        if remove and name in scope:
            scope.remove(name)
            if name in scope.root:
                self.warn(f"Cannot remove global symbol: {name}")
            el.detach()
            return
        if default is not None:
            if scope_kind is not None:
                self.warn(f"{name}: default property value can only be defined on local scope")
            if name not in scope:
                value = default
            else:
                el.detach()
                return
        stored: Any = value
        if value is None:
            name = "**" + name
            stored = el
        el.detach()
        lazy = self.boolean(self.eval_text(lazy_t or "true", scope), lazy_t)
        target: Scope = scope
        if scope_kind == "global":
            target = scope.top()
            lazy = False
        elif scope_kind == "parent":
            if scope.parent is None:
                self.warn(f"{name}: no parent scope at global scope ")
                return
            target = scope.parent
            lazy = False
            if not isinstance(scope, NameSpace):
                while isinstance(target, NameSpace) and target.parent is not None:
                    target = target.parent
        if not lazy and isinstance(stored, str):
            stored = self.eval_text(stored, scope)
        if name in target.root:
            self.warn(f"redefining global symbol: {name}")
        target.define(name, stored, lazy=lazy, where=el.loc)

    def define_macro(self, el: Element, macros: MacroTable) -> None:
        self.remove_previous_comments(el)
        (name,), (params,) = self.attrs(el, ["name"], ["params"])
        if name == "call":
            msg = "Invalid use of macro name 'call'"
            raise XacroError(msg, el.loc)
        if "." in name:
            msg = f"macro names must not contain '.' (reserved for namespaces): {name}"
            raise XacroError(msg, el.loc)
        if name.startswith("xacro:"):
            self.warn(f"macro names must not contain prefix 'xacro:': {name}", el.loc)
            name = name[6:]
        plist, defaults = parse_macro_params(params or "")
        target = macros.top() if self.dialect in (Dialect.MELODIC, Dialect.KINETIC) else macros
        target.macros[name] = Macro(name, el, plist, defaults)
        self.macro_names.add(name)
        if target.parent is not None and self.calls:
            self.nested_definitions.setdefault(name, self.calls[-1][0].name)
        el.detach()

    def include(
        self, el: Element, macros: MacroTable, scope: Scope, *, evaluate: bool = True
    ) -> None:
        (spec,), (ns_t, optional_t) = self.attrs(el, ["filename"], ["ns", "optional"])
        ns_macros, ns_scope = macros, scope
        if ns_t:
            ns = str(self.eval_text(ns_t, scope))
            ns_macros = MacroTable()
            macros.macros[ns] = ns_macros
            ns_scope = NameSpace(scope)
            if ns in scope.root:
                self.warn(f"redefining global symbol: {ns}")
            scope.vars[ns] = ns_scope
            scope.lazy.pop(ns, None)
        optional = self.boolean(optional_t, None) if optional_t is not None else False
        if el.first_element() is not None:
            self.warn("Child elements of a <xacro:include> tag are ignored", el.loc)
        included: list[Element] = []
        for filename in self.include_files(spec, scope):
            try:
                doc = self.open_included(filename, el.loc)
            except _MissingIncludeError:
                if optional:
                    continue
                raise
            self.files.append(filename)
            try:
                root = doc.root
                if evaluate:
                    self.eval_all(root, ns_macros, ns_scope)
            except XacroError as err:
                err.add_trail("included from", el.loc or SourceLocation("<string>"))
                raise
            finally:
                self.files.pop()
            included.append(root)
            self.import_namespaces(el.parent, root.attrs)
        self.remove_previous_comments(el)
        for root in included:
            _move_children(root, el)
        el.detach()

    def include_files(self, spec: str, scope: Scope) -> Iterator[str]:
        filename = self.abs_filename(str(self.eval_text(spec, scope)))
        if re.search(r"[*[?]+", filename):
            names = sorted(glob.glob(os.path.join(self.root_dir, filename)))
            if self.root_dir != os.curdir:
                names = [os.path.relpath(n, self.root_dir) for n in names]
            if not names:
                self.warn(f'Include tag\'s filename spec "{filename}" matched no files.')
        else:
            names = [filename]
        for name in names:
            self.includes.append(name)
            yield name

    def open_included(self, filename: str, at: SourceLocation | None) -> Document:
        path = os.path.join(self.root_dir, filename)
        if not os.path.isfile(path):
            reason = "is a directory" if os.path.isdir(path) else "no such file"
            msg = f"cannot include {filename}: {reason}"
            raise _MissingIncludeError(msg, at)
        self.check_readable(filename, at)
        try:
            return parse_file(path, display=filename)
        except XacroError:
            raise
        except ParseError as err:
            raise XacroError(err.message, err.location, hint=err.hint) from None


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


def _move_children(content: Element, before: Node) -> None:
    parent = before.parent
    assert parent is not None
    parent.move_children_before(content, before)


def _did_you_mean(name: str, scope: Scope) -> str | None:
    known: set[str] = set()
    s: Scope | None = scope
    while s is not None:
        known.update(k for k in s.vars if not k.startswith("*"))
        s = s.parent
    hint = did_you_mean(name, known, most=3) or did_you_mean(name, scope.root, most=3, cutoff=0.75)
    if hint is not None:
        return hint
    return "properties must be defined (xacro:property) before the expression is evaluated"


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
