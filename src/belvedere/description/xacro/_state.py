"""One xacro run's state and what every part of its walk uses: diagnostics, the files it
reads (``load_yaml``, ``abs_filename``, the package-root check), text evaluation, a xacro
tag's attributes, and moving nodes."""

from __future__ import annotations

import logging
import os
from collections.abc import Callable
from typing import Any

from belvedere.bounded import YAML_TEXT_BYTES, LimitError, read_regular_text
from belvedere.description.xacro._builtins import to_yaml_value
from belvedere.description.xacro._dialects import Dialect, XacroWarning
from belvedere.description.xacro._errors import XacroError
from belvedere.description.xacro._expr import EXPR
from belvedere.description.xacro._interpreter import Compiled, ExpressionError, evaluate
from belvedere.description.xacro._macros import Macro
from belvedere.description.xacro._substitutions import Substitutions
from belvedere.description.xacro._symbols import (
    Scope,
    boolean,
    kinetic_boolean,
    make_global_symbols,
)
from belvedere.description.xacro._text import Part, program, programs, python2_str
from belvedere.errors import SourceLocation, did_you_mean
from belvedere.locate import pinpoint
from belvedere.packages import PackageIndex
from belvedere.xmldom import Comment, Element, Node, Text

__all__ = ["ProcessorState"]

logger = logging.getLogger("belvedere.xacro")


class ProcessorState:
    """One run of xacro over one document: its state, diagnostics, files and evaluation."""

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
