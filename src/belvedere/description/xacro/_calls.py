"""Macro calls: finding the macro, binding its parameters and blocks, expanding its body."""

from __future__ import annotations

import difflib
from typing import TYPE_CHECKING, Any, Final

from belvedere.description.xacro._dialects import Dialect, unprefixed_call
from belvedere.description.xacro._errors import XacroError
from belvedere.description.xacro._macros import Macro, MacroTable
from belvedere.description.xacro._symbols import Scope
from belvedere.errors import SourceLocation
from belvedere.xmldom import Element, Node

__all__ = ["MAX_MACRO_DEPTH", "MacroCalls"]

MAX_MACRO_DEPTH: Final = 2000


class MacroCalls:
    """The macro-call part of the processor (a mixin over its state and its walk)."""

    if TYPE_CHECKING:
        dialect: Dialect
        calls: list[tuple[Macro, SourceLocation | None]]
        macro_names: set[str]
        nested_definitions: dict[str, str]
        legacy_sites: list[tuple[SourceLocation, str]]

        def eval_text(self, text: str, scope: Scope) -> Any: ...
        def eval_all(self, node: Element, macros: MacroTable, scope: Scope) -> None: ...
        def warn(
            self,
            message: str,
            location: SourceLocation | None = None,
            *,
            legacy: str | None = None,
        ) -> None: ...
        def warn_once(
            self,
            key: str,
            message: str,
            location: SourceLocation | None = None,
            *,
            legacy: str | None = None,
        ) -> None: ...
        def remove_previous_comments(self, node: Node) -> None: ...
        def import_namespaces(self, parent: Node | None, attrs: dict[str, str]) -> None: ...
        @staticmethod
        def splice(node: Node, content: Element) -> None: ...

    def resolve_macro(
        self, name: str, macros: MacroTable, scope: Scope
    ) -> tuple[MacroTable, Scope, Macro] | None:
        found = macros.get(name)
        if isinstance(found, Macro):
            return macros, scope, found
        parts = name.split(".")
        if len(parts) < 2:
            return None
        m_tab: MacroTable | Macro | None = macros
        s_tab: Any = scope
        for ns in parts[:-1]:
            if not isinstance(m_tab, MacroTable):
                return None
            m_tab = m_tab.get(ns)
            try:
                s_tab = s_tab[ns]
            except (KeyError, TypeError):
                return None
        if not isinstance(m_tab, MacroTable) or not isinstance(s_tab, Scope):
            return None
        found = m_tab.get(parts[-1])
        if isinstance(found, Macro):
            return m_tab, s_tab, found
        return None

    def macro_call(self, el: Element, macros: MacroTable, scope: Scope) -> bool:
        tag = el.tag
        if tag == "xacro:call":
            if "macro" not in el.attrs:
                msg = "xacro:call: missing attribute 'macro'"
                raise XacroError(msg, el.loc)
            name = str(self.eval_text(el.attrs.pop("macro"), scope))
            if not name:
                msg = "xacro:call is missing the 'macro' attribute"
                raise XacroError(msg, el.loc)
            el.tag = "xacro:" + name
            tag = el.tag
        if tag.startswith("xacro:"):
            name = tag[6:]
            resolved = self.resolve_macro(name, macros, scope)
            if resolved is None:
                msg = f"unknown macro name: {tag}"
                raise XacroError(msg, el.loc, hint=self._near_macros(name, macros))
        else:
            if tag not in self.macro_names:
                return False
            resolved = self.resolve_macro(tag, macros, scope)
            if resolved is None:
                return False
            if not self._expand_unprefixed(el, resolved[2]):
                return False
            if el.loc is not None:
                self.legacy_sites.append((el.loc, tag))
        self.expand(el, *resolved, caller_macros=macros, caller_scope=scope)
        return True

    def _expand_unprefixed(self, el: Element, macro: Macro) -> bool:
        """Whether an unprefixed tag that names a macro is expanded as a call (with the
        dialect's warning either way)."""
        expand, key, message = unprefixed_call(
            self.dialect, el, macro, calling=[m.name for m, _ in self.calls]
        )
        if expand and self.dialect is Dialect.AUTO:  # each place: -v lists what --fix rewrites
            self.warn_once(f"{key}@{el.loc}", message, el.loc, legacy=el.tag)
        else:
            self.warn_once(key, message, el.loc)
        return expand

    def _near_macros(self, name: str, macros: MacroTable) -> str | None:
        if name in self.nested_definitions:
            return (
                f"'{name}' was defined inside macro '{self.nested_definitions[name]}', so it "
                "exists only there; ROS Melodic and Kinetic made such macros global "
                "(--dialect melodic)"
            )
        known: list[str] = []
        t: MacroTable | None = macros
        while t is not None:
            known.extend(k for k, v in t.macros.items() if isinstance(v, Macro))
            t = t.parent
        close = difflib.get_close_matches(name, known, n=3)
        if close:
            return "did you mean " + ", ".join(f"xacro:{c}" for c in close) + "?"
        if known:
            return "defined macros: " + ", ".join(sorted(set(known))[:12])
        return "no macros are defined at this point (macros must be defined before use)"

    def expand(
        self,
        el: Element,
        macro_tab: MacroTable,
        macro_scope: Scope,
        m: Macro,
        *,
        caller_macros: MacroTable,
        caller_scope: Scope,
    ) -> None:
        if len(self.calls) >= MAX_MACRO_DEPTH:
            chain = " -> ".join(c[0].name for c in self.calls[-6:])
            msg = (
                f"macro nesting deeper than {MAX_MACRO_DEPTH} levels (… {chain} -> {m.name}): "
                "a macro that calls itself without end?"
            )
            raise XacroError(msg, el.loc, hint="guard the recursive call with xacro:if")
        body = m.body.clone()
        self.calls.append((m, el.loc))
        try:
            self._expand(el, body, macro_tab, macro_scope, m, caller_macros, caller_scope)
        except XacroError as err:
            err.add_trail(f"in macro '{m.name}' called from", el.loc or SourceLocation("?"))
            raise
        finally:
            self.calls.pop()

    def _expand(
        self,
        el: Element,
        body: Element,
        macro_tab: MacroTable,
        macro_scope: Scope,
        m: Macro,
        caller_macros: MacroTable,
        caller_scope: Scope,
    ) -> None:
        scope = Scope(macro_scope)
        # Melodic evaluated bodies with the caller's macro table, so definitions leaked.
        local_macros = (
            macro_tab
            if self.dialect in (Dialect.MELODIC, Dialect.KINETIC)
            else MacroTable(macro_tab)
        )
        remaining = list(m.params)
        root = scope.root
        for name, value in list(el.attrs.items()):
            if name not in remaining:
                msg = f'Invalid parameter "{name}" of macro {m.name!r}'
                expected = ", ".join(p for p in m.params if not p.startswith("*"))
                raise XacroError(msg, el.loc, hint=f"parameters: {expected or '(none)'}")
            remaining.remove(name)
            if name in root:
                self.warn(f"redefining global symbol: {name}")
            scope.define(name, self.eval_text(value, caller_scope), lazy=False)
            el.attrs[name] = ""
        self.eval_all(el, caller_macros, caller_scope)

        block = el.first_element()
        for param in list(remaining):
            if param.startswith("*"):
                if block is None:
                    msg = f"Not enough blocks for macro {m.name!r} (missing {param})"
                    raise XacroError(msg, el.loc)
                remaining.remove(param)
                scope.vars[param] = block
                nxt = block.next
                while nxt is not None and not isinstance(nxt, Element):
                    nxt = nxt.next
                block = nxt
        if block is not None:
            msg = f'Unused block "{block.tag}" in call of macro {m.name!r}'
            raise XacroError(msg, block.loc)

        for param in list(remaining):
            if param.startswith("*"):
                continue
            forward, default = m.defaults.get(param, (None, None))
            if forward is None and default is None:
                continue
            if forward is None:
                assert default is not None
                value = self.eval_text(default, caller_scope)
            elif forward in caller_scope:
                value = caller_scope[forward]
            elif default is not None:
                value = self.eval_text(default, caller_scope)
            else:
                msg = f"Undefined property to forward: {forward}"
                raise XacroError(msg, el.loc)
            if param in root:
                self.warn(f"redefining global symbol: {param}")
            scope.define(param, value, lazy=False)
            remaining.remove(param)
        if remaining:
            msg = f"Undefined parameters [{','.join(remaining)}] of macro {m.name!r}"
            raise XacroError(msg, el.loc)

        self.eval_all(body, local_macros, scope)
        self.remove_previous_comments(el)
        self.import_namespaces(el.parent, body.attrs)
        self.splice(el, body)
