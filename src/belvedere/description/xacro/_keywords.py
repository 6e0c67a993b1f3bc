"""xacro's keyword tags: ``insert_block``, ``property``, ``macro`` and ``include``."""

from __future__ import annotations

import glob
import keyword
import os
import re
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from belvedere.description.xacro._dialects import Dialect
from belvedere.description.xacro._errors import XacroError
from belvedere.description.xacro._macros import Macro, MacroTable, parse_macro_params
from belvedere.description.xacro._state import ProcessorState, _move_children
from belvedere.description.xacro._symbols import NameSpace, Scope
from belvedere.errors import ParseError, SourceLocation
from belvedere.xmldom import Document, Element, parse_file

__all__ = ["Keywords"]


def _is_valid_name(name: str) -> bool:
    return name.isidentifier() and not keyword.iskeyword(name)


class _MissingIncludeError(XacroError):
    """An include whose file does not exist (skipped when the include is optional)."""


class Keywords(ProcessorState):
    """The keyword tags' part of the processor (over its state; the walk calls them)."""

    if TYPE_CHECKING:

        def eval_all(self, node: Element, macros: MacroTable, scope: Scope) -> None: ...

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
