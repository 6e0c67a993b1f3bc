"""Reading roslaunch XML into a :class:`LaunchConfig`, as roslaunch does it.

Tags: ``launch``, ``arg``, ``param``, ``rosparam``, ``node``, ``include``, ``group``,
``remap``, ``env``, ``machine`` (a warning: everything runs here), ``test`` (skipped).
Substitutions: ``$(find)``, ``$(arg)``, ``$(env)``, ``$(optenv)``, ``$(eval)``, ``$(anon)``,
``$(dirname)``. ``if``/``unless`` accept true/false/1/0 only, as roslaunch. Errors name the
file and line.

Launch files from elsewhere are read within bounds: every file they name (``<include>``,
``textfile``/``binfile``, ``<rosparam file>``) must be a regular file — a FIFO, a device or a
directory is refused without waiting on it — of at most
:data:`~belvedere.bounded.TEXT_FILE_BYTES` (:data:`~belvedere.bounded.YAML_TEXT_BYTES` for
YAML); a ``<param command>`` is bounded in output and time (:func:`.run_program`). ``$(eval)``
runs no program (its expressions are evaluated, never executed), and ``<rosparam
command>`` is load, dump or delete only. Each refusal is an error at the element's line.
"""

from __future__ import annotations

import os
import re
import uuid
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from belvedere.bounded import (
    TEXT_FILE_BYTES,
    YAML_TEXT_BYTES,
    LimitError,
    read_regular,
    read_regular_text,
)
from belvedere.description.xacro import XacroError
from belvedere.description.xacro._interpreter import ExpressionError
from belvedere.description.xacro._substitutions import Substitutions
from belvedere.errors import BelvedereError, ParseError, SourceLocation, did_you_mean
from belvedere.launch._model import LaunchConfig, LaunchError, LaunchFile, LaunchNode
from belvedere.launch._names import canonical, child_namespace, global_ns, is_legal, ns_join
from belvedere.launch._values import param_bool, param_command, test_limits, typed_value
from belvedere.locate import pinpoint
from belvedere.packages import PackageIndex
from belvedere.xmldom import Element, parse_file
from belvedere.yamlfile import YamlDocument, load_yaml, load_yaml_file

__all__ = ["load_launch"]

_SUBSTITUTION = re.compile(r"\$\(([^()]*(?:\([^()]*\)[^()]*)*)\)")
_KNOWN_TAGS = frozenset(
    {"arg", "param", "rosparam", "node", "include", "group", "remap", "env", "machine", "test"}
)


@dataclass
class _Scope:
    """What a place in a launch file sees: its namespace, args, remappings and env."""

    file: str
    namespace: str = "/"
    """With a trailing slash, as roslaunch keeps it (``/``, ``/robot1/``)."""
    args: dict[str, str] = field(default_factory=dict)
    passed: dict[str, str] = field(default_factory=dict)
    used: set[str] = field(default_factory=set)
    remappings: tuple[tuple[str, str], ...] = ()
    env: tuple[tuple[str, str], ...] = ()
    included: list[tuple[str, list[str]]] = field(default_factory=list)
    """(file, the args it declares) of each file this one includes, and theirs, in order (an
    unknown arg's hint lists them; a group shares its file's list)."""
    private: list[_Private] = field(default_factory=list)
    """``~params`` declared outside a node: every later node in this scope gets them. A group
    starts with a copy; an included file, as roslaunch has it, shares the list once it holds
    one (so a ``~param`` declared in the included file reaches the includer's later nodes too)
    and starts a list of its own while it is empty."""

    def child(self, namespace: str) -> _Scope:
        """The scope of a ``<group>``."""
        return replace(self, namespace=namespace, private=list(self.private))


@dataclass(frozen=True)
class _Private:
    """A ``~param`` outside a node: its name without the ``~``, its value, where it is."""

    name: str
    value: Any
    source: SourceLocation | None


def load_launch(
    path: str | Path,
    *,
    args: Mapping[str, str] | None = None,
    packages: PackageIndex | None = None,
    tests: bool = False,
) -> LaunchConfig:
    """Read a launch file (and what it includes) with ``args`` given as ``name:=value``;
    ``tests``: for rostest, whose ``<test>`` elements are no notes."""
    packages = packages or PackageIndex.from_environment(near=str(path))
    loader = _Loader(packages, with_tests=tests)
    loader.file(Path(path), _Scope(str(path), passed=dict(args or {})), top=True)
    return loader.config


class _Loader:
    def __init__(self, packages: PackageIndex, *, with_tests: bool = False) -> None:
        self.packages = packages
        self.config = LaunchConfig()
        self.including: list[str] = []
        self.anon: dict[str, str] = {}
        self.with_tests = with_tests

    # --- files -----------------------------------------------------------------------------------
    def file(
        self, path: Path, scope: _Scope, *, top: bool = False, at: SourceLocation | None = None
    ) -> None:
        key = str(path.resolve())
        if key in self.including:
            chain = " -> ".join([*self.including, key])
            msg = f"include cycle: {chain}"
            raise LaunchError(msg, at)
        if not os.path.exists(path):
            msg = f"launch file {str(path)!r} does not exist"
            siblings = path.parent.glob("*.launch*") if path.parent.is_dir() else []
            raise LaunchError(msg, at, hint=did_you_mean(path.name, (p.name for p in siblings)))
        try:
            doc = parse_file(path, namespaces=False, keep_blank=False)
        except ParseError as err:
            if err.location is None:  # not a file it can read (a FIFO, a directory…)
                err.location = at
            raise _with_conflict_hint(err, path) from None
        root = doc.root
        if root.tag != "launch":
            msg = f"a launch file's root must be <launch>, not <{root.tag}>"
            raise LaunchError(msg, root.loc)
        self.config.files.append(LaunchFile("launch", str(path)))
        if "deprecated" in root.attrs:
            self.config.warnings.append(
                f"{root.loc}: warning: this launch file is deprecated: {root.attrs['deprecated']}"
            )
        self.including.append(key)
        try:
            self.children(root, scope)
        finally:
            self.including.pop()
        unused = sorted(set(scope.passed) - scope.used)
        if unused:
            where = "the command line" if top else f"the <include> at {at}"
            msg = f"unused args {unused} given by {where} for {path}"
            raise LaunchError(msg, at or root.loc, hint=_declared_hint(unused, scope))

    def children(self, el: Element, scope: _Scope) -> None:
        for child in el.elements():
            if not self.active(child, scope):
                continue
            handler = getattr(self, f"tag_{child.tag}", None)
            if handler is None:
                self.config.warnings.append(
                    f"{child.loc}: warning: unknown tag <{child.tag}> ignored"
                )
                continue
            handler(child, scope)

    # --- substitutions ---------------------------------------------------------------------------
    def subst(self, text: str, scope: _Scope, at: SourceLocation | None) -> str:
        if "$(" not in text:
            return text
        stripped = text.strip()
        if stripped.startswith("$(eval ") and stripped.endswith(")"):
            return self._eval(stripped[7:-1], scope, at)

        def one(match: re.Match[str]) -> str:
            inner = match.group(1).strip()
            words = inner.split()
            if words and words[0] == "anon":
                if len(words) != 2:
                    msg = f"$(anon NAME) takes one name: $({inner})"
                    raise LaunchError(msg, at)
                return self.anon.setdefault(words[1], f"{words[1]}_{uuid.uuid4().hex[:12]}")
            if words and words[0] == "arg" and len(words) == 2 and words[1] not in scope.args:
                declared = ", ".join(sorted(scope.args)) or "none"
                msg = f"arg {words[1]!r} is not defined (declared here: {declared})"
                raise LaunchError(msg, at, hint=f'declare it: <arg name="{words[1]}" …/>')
            if words and words[0] == "eval":
                msg = "$(eval …) must be the whole attribute value"
                raise LaunchError(msg, at)
            try:
                return self._substitutions(scope, at)(inner)
            except XacroError as err:
                message = err.message.replace("xacro:arg", "arg")
                raise LaunchError(message, at, hint=err.hint) from None

        return _SUBSTITUTION.sub(one, text)

    def _substitutions(self, scope: _Scope, at: SourceLocation | None) -> Substitutions:
        return Substitutions(
            args=scope.args,
            packages=self.packages,
            root_dir=os.getcwd(),
            current_file=lambda: scope.file,
            here=lambda: at,
        )

    def _eval(self, expr: str, scope: _Scope, at: SourceLocation | None) -> str:
        try:
            value = self._substitutions(scope, at)("eval " + expr)
        except ExpressionError as err:
            msg = f"$(eval {expr}): {err.message}"
            where = at if err.offset is None else pinpoint(at, f"$(eval {expr}", 7 + err.offset)
            raise LaunchError(msg, where, hint=err.hint) from None
        except XacroError as err:
            msg = f"$(eval {expr}): {err.message}"
            raise LaunchError(msg, at, hint=err.hint) from None
        except BelvedereError:
            raise
        except Exception as err:  # noqa: BLE001 (any error of the user's expression)
            msg = f"$(eval {expr}) failed: {err}"
            raise LaunchError(msg, at) from None
        return value

    def attr(self, el: Element, name: str, scope: _Scope, default: str | None = None) -> str | None:
        value = el.attrs.get(name)
        if value is None:
            return default
        return self.subst(value, scope, el.loc)

    def required(self, el: Element, name: str, scope: _Scope) -> str:
        value = self.attr(el, name, scope)
        if value is None:
            msg = f"<{el.tag}> needs a {name!r} attribute"
            raise LaunchError(msg, el.loc)
        return value

    def boolean(self, el: Element, name: str, scope: _Scope, default: bool) -> bool:
        value = self.attr(el, name, scope)
        if value is None:
            return default
        return param_bool(value, f"{name}={value!r}", el.loc)

    def active(self, el: Element, scope: _Scope) -> bool:
        if_value = self.attr(el, "if", scope)
        unless_value = self.attr(el, "unless", scope)
        if if_value is not None and unless_value is not None:
            msg = "an element cannot have both 'if' and 'unless'"
            raise LaunchError(msg, el.loc)
        if if_value is not None:
            return param_bool(if_value, f"if={if_value!r}", el.loc)
        if unless_value is not None:
            return not param_bool(unless_value, f"unless={unless_value!r}", el.loc)
        return True

    # --- tags ------------------------------------------------------------------------------------
    def tag_arg(self, el: Element, scope: _Scope) -> None:
        name = self.required(el, "name", scope)
        value = self.attr(el, "value", scope)
        default = self.attr(el, "default", scope)
        if value is not None and default is not None:
            msg = f"arg {name!r} has both a value and a default"
            raise LaunchError(msg, el.loc)
        if name in scope.args:
            msg = f"arg {name!r} is declared twice"
            raise LaunchError(msg, el.loc)
        if value is not None:
            if name in scope.passed:
                msg = f"cannot override arg {name!r}, which has a fixed value in this file"
                raise LaunchError(msg, el.loc)
            scope.args[name] = value
        elif name in scope.passed:
            scope.args[name] = scope.passed[name]
            scope.used.add(name)
        elif default is not None:
            scope.args[name] = default
        else:
            msg = f"required arg {name!r} is not set"
            doc = el.attrs.get("doc")
            raise LaunchError(
                msg, el.loc, hint=f"pass {name}:=VALUE" + (f" ({doc})" if doc else "")
            )
        if name in scope.passed:
            scope.used.add(name)

    def tag_param(
        self, el: Element, scope: _Scope, node_params: list[_Private] | None = None
    ) -> None:
        """A ``<param>``: inside a node (``node_params``) it is the node's whatever its name
        says (``x``, ``~x`` and ``/x`` all become ``/ns/node/x``); ``~x`` elsewhere waits for
        the nodes declared after it; any other name joins the namespace."""
        raw = self.attr(el, "name", scope)
        if raw is None:
            msg = "<param> needs a 'name' attribute"
            raise LaunchError(msg, el.loc)
        name = raw.strip()
        value = self._param_value(el, scope)
        self._check_name(name, el)
        if node_params is not None or name.startswith("~"):
            target = scope.private if node_params is None else node_params
            bare = name[1:] if name.startswith("~") else name
            target[:] = [p for p in target if p.name != bare]
            target.append(_Private(bare, value, el.loc))
            return
        self.config.set_param(canonical(ns_join(scope.namespace, name)), value, el.loc)

    def _check_name(self, name: str, el: Element) -> None:
        """roslaunch sets a parameter under any name; one ROS tools cannot look up is only
        worth a warning."""
        if not is_legal(name):
            self.config.warnings.append(
                f"{el.loc}: warning: parameter name {name!r} is not a legal ROS name (letters, "
                "digits, '_' and '/'): it is set as written, but nodes may not find it"
            )

    def _param_value(self, el: Element, scope: _Scope) -> Any:
        kind = (el.attrs.get("type") or "auto").strip().lower()
        sources = [k for k in ("value", "textfile", "binfile", "command") if k in el.attrs]
        if len(sources) != 1:
            msg = "<param> needs exactly one of value, textfile, binfile, command"
            raise LaunchError(msg, el.loc)
        source = sources[0]
        raw = self.attr(el, source, scope) or ""
        if source == "value":
            return typed_value(raw.strip(), kind, el.loc)
        if source in ("textfile", "binfile"):
            try:
                data = read_regular(
                    raw, limit=TEXT_FILE_BYTES, what=source, name=repr(raw), at=el.loc
                )
            except LimitError as err:
                raise LaunchError(err.message, err.location) from None
            read = "binary" if source == "binfile" else "urdf" if raw.endswith(".urdf") else "text"
            self.config.files.append(LaunchFile(read, raw))
            if source == "binfile":
                return data
            return typed_value(data.decode("utf-8", errors="replace"), kind, el.loc)
        output = param_command(raw, el.loc, self.packages, self.config.files)
        return typed_value(output, kind, el.loc)

    def tag_rosparam(self, el: Element, scope: _Scope, node_ns: str | None = None) -> None:
        """``<rosparam>``: ``ns`` and ``param`` join (either may be global), then join the
        node's private namespace inside a node (``node_ns``), the scope's elsewhere; keys of
        the YAML join the same way, so ``{"/k": v}`` is the global ``/k`` even in a node."""
        command = self.attr(el, "command", scope, "load") or "load"
        ns = self.attr(el, "ns", scope)
        param = ns_join(ns or "", self.attr(el, "param", scope) or "")
        base = node_ns or scope.namespace
        target = ns_join(base, param) if param else base
        if command == "delete":
            self.config.deletions.append(canonical(target))
            return
        if command == "dump":
            file = self.attr(el, "file", scope)
            if not file:
                msg = "<rosparam command='dump'> needs a file"
                raise LaunchError(msg, el.loc)
            self.config.dumps.append((file, canonical(target)))
            return
        if command != "load":
            msg = f"<rosparam command={command!r}>: expected load, dump or delete"
            raise LaunchError(msg, el.loc)
        file = self.attr(el, "file", scope)
        subst_value = self.boolean(el, "subst_value", scope, False)
        if file:
            if subst_value:
                try:
                    text = read_regular_text(
                        file, limit=YAML_TEXT_BYTES, what="", name=repr(file), at=el.loc
                    )
                except LimitError as err:
                    raise LaunchError(err.message, err.location) from None
                doc = load_yaml(self.subst(text, scope, el.loc), path=file)
            else:
                doc = load_yaml_file(file, requested_at=el.loc)
            self.config.files.append(LaunchFile("yaml", file))
        else:
            text = el.text_content()
            if subst_value:
                text = self.subst(text, scope, el.loc)
            line = el.loc.line if el.loc else 0
            # keep line numbers: pad so the YAML's lines are the launch file's lines
            doc = load_yaml("\n" * max(0, line - 1) + text, path=scope.file)
        data = doc.data
        if data is None:
            data = {}
        if not isinstance(data, dict) and not param:
            msg = "<rosparam> YAML must be a mapping unless the element has a 'param'"
            raise LaunchError(msg, el.loc)
        self._unroll(target, data, el.loc, doc, ())

    def _unroll(
        self,
        name: str,
        value: Any,
        at: SourceLocation | None,
        doc: YamlDocument,
        keys: tuple[str, ...],
    ) -> None:
        """Set a rosparam value: a mapping sets each of its leaves (an empty one, nothing),
        each remembering its line in the YAML (a node names it in a bad value's error)."""
        if isinstance(value, dict):
            for key, sub in value.items():
                self._unroll(ns_join(name, str(key)), sub, at, doc, (*keys, str(key)))
            return
        if canonical(name) == "/":
            msg = "only a mapping can be loaded into the root namespace '/'"
            raise LaunchError(msg, at)
        self.config.set_param(canonical(name), value, doc.location(*keys) if keys else at)

    def tag_node(self, el: Element, scope: _Scope, *, test: bool = False) -> None:
        """A ``<node>`` (or ``<test>``): its ``<param>``s, ``<remap>``s and ``<env>``s, and the
        ``~params`` declared before it in its scope."""
        pkg = self.required(el, "pkg", scope)
        kind = self.required(el, "type", scope)
        name = self.attr(el, "name", scope)
        test_name, time_limit, retry = None, 60.0, 0
        if test:
            test_name = self.required(el, "test-name", scope)
            name = name or test_name
            time_limit, retry = test_limits(
                self.attr(el, "time-limit", scope), self.attr(el, "retry", scope), el.loc
            )
        if not name:
            msg = f"<{el.tag}> needs a name"
            raise LaunchError(msg, el.loc)
        if not is_legal(name) or "/" in name:
            self.config.warnings.append(
                f"{el.loc}: warning: node name {name!r} is not a legal ROS base name"
            )
        ns = child_namespace(scope.namespace, self.attr(el, "ns", scope))
        private = global_ns(ns_join(ns, name))
        if self.boolean(el, "clear_params", scope, False):
            self.config.clear.append(canonical(private))
        remaps = list(scope.remappings)
        env = list(scope.env)
        node_params: list[_Private] = []
        for child in el.elements():
            if not self.active(child, scope):
                continue
            if child.tag == "remap":
                remaps = _remapped(remaps, self._remap(child, scope))
            elif child.tag == "param":
                self.tag_param(child, scope, node_params)
            elif child.tag == "rosparam":
                self.tag_rosparam(child, scope, node_ns=private)
            elif child.tag == "env":
                env.append(self._env(child, scope))
            else:
                self.config.warnings.append(
                    f"{child.loc}: warning: <{child.tag}> inside <{el.tag}> ignored"
                )
        for param in [*scope.private, *node_params]:
            self.config.set_param(canonical(private + param.name), param.value, param.source)
        prefix = self.attr(el, "launch-prefix", scope)
        if prefix:
            self.config.warnings.append(
                f"{el.loc}: note: launch-prefix {prefix!r} ignored (nodes run in this process)"
            )
        if "machine" in el.attrs:
            self.config.warnings.append(
                f"{el.loc}: note: machine={el.attrs['machine']!r}: the node runs on this machine"
            )
        respawn = self.boolean(el, "respawn", scope, False)
        if respawn and not test and self.boolean(el, "required", scope, False):
            msg = "Invalid <node> tag: respawn and required cannot both be set to true"
            raise LaunchError(msg, el.loc, hint="a required node ends the launch when it exits")
        (self.config.tests if test else self.config.nodes).append(
            LaunchNode(
                pkg=pkg,
                type=kind,
                name=name,
                namespace=canonical(ns),
                args=self.attr(el, "args", scope, "") or "",
                output=self.attr(el, "output", scope, "log") or "log",
                respawn=respawn,
                respawn_delay=typed_value(
                    self.attr(el, "respawn_delay", scope, "0") or "0", "double", el.loc
                ),
                required=self.boolean(el, "required", scope, False),
                cwd=self.attr(el, "cwd", scope),
                launch_prefix=prefix,
                remappings=tuple(remaps),
                env=tuple(env),
                source=el.loc,
                test_name=test_name,
                time_limit=time_limit,
                retry=retry,
            )
        )

    def tag_test(self, el: Element, scope: _Scope) -> None:
        """A ``<test>``, as roslaunch reads it: ``launch`` skips it, ``belvedere test`` runs it."""
        if not self.with_tests:
            self.config.warnings.append(
                f"{el.loc}: note: <test> {el.attrs.get('test-name', '')} skipped (tests are "
                "not run by belvedere launch: belvedere test runs them)"
            )
        self.tag_node(el, scope, test=True)

    def tag_include(self, el: Element, scope: _Scope) -> None:
        file = self.required(el, "file", scope)
        include_ns = self.attr(el, "ns", scope)
        ns = child_namespace(scope.namespace, include_ns)
        if self.boolean(el, "clear_params", scope, False):
            if not include_ns:
                msg = "clear_params on an <include> needs an ns"
                raise LaunchError(msg, el.loc)
            self.config.clear.append(canonical(ns))
        passed: dict[str, str] = {}
        if self.boolean(el, "pass_all_args", scope, False):
            passed.update(scope.args)
        env = list(scope.env)
        for child in el.elements():
            if not self.active(child, scope):
                continue
            if child.tag == "arg":
                name = self.required(child, "name", scope)
                value = self.attr(child, "value", scope)
                if value is None:
                    value = self.attr(child, "default", scope)
                if value is None:
                    msg = f"<arg name={name!r}> in an <include> needs a value"
                    raise LaunchError(msg, child.loc)
                passed[name] = value
            elif child.tag == "env":
                env.append(self._env(child, scope))
        inner = _Scope(
            file,
            namespace=ns,
            passed=passed,
            remappings=scope.remappings,
            env=tuple(env),
            private=scope.private or [],
        )
        if self.boolean(el, "pass_all_args", scope, False):
            inner.used |= set(scope.args)  # passing all is not "unused"
        self.file(Path(file), inner, at=el.loc)
        scope.included.append((file, sorted(inner.args)))
        scope.included.extend(inner.included)

    def tag_group(self, el: Element, scope: _Scope) -> None:
        group_ns = self.attr(el, "ns", scope)
        ns = child_namespace(scope.namespace, group_ns)
        if self.boolean(el, "clear_params", scope, False):
            self.config.clear.append(canonical(ns))
        inner = scope.child(ns)
        self.children(el, inner)
        # args declared in a group belong to the file (roslaunch scoping)
        scope.args.update(inner.args)
        scope.used |= inner.used

    def _remap(self, el: Element, scope: _Scope) -> tuple[str, str]:
        pair = (
            canonical(self.required(el, "from", scope)),
            canonical(self.required(el, "to", scope)),
        )
        for name in pair:
            if not name or not is_legal(name):
                msg = f"remap {pair[0]!r} -> {pair[1]!r}: {name!r} is not a valid ROS name"
                raise LaunchError(msg, el.loc)
        return pair

    def tag_remap(self, el: Element, scope: _Scope) -> None:
        scope.remappings = tuple(_remapped(list(scope.remappings), self._remap(el, scope)))

    def _env(self, el: Element, scope: _Scope) -> tuple[str, str]:
        name = self.required(el, "name", scope)
        if not name:
            msg = "<env> needs a non-empty name"
            raise LaunchError(msg, el.loc)
        return name, self.required(el, "value", scope)

    def tag_env(self, el: Element, scope: _Scope) -> None:
        scope.env = (*scope.env, self._env(el, scope))

    def tag_machine(self, el: Element, scope: _Scope) -> None:
        self.config.warnings.append(
            f"{el.loc}: note: <machine {el.attrs.get('name', '')}> ignored: everything runs here"
        )


def _declared_hint(unused: list[str], scope: _Scope) -> str:
    """What the file declares (and its includes), and the declared arg each unknown one is
    likely a misspelling of."""
    near = [hint for name in unused if (hint := did_you_mean(name, scope.args))]
    lines = [*near, f"args this file declares: {', '.join(sorted(scope.args)) or 'none'}"]
    lines.extend(f"{file} declares: {', '.join(args) or 'none'}" for file, args in scope.included)
    return "\n        ".join(lines)  # under the first line, after "  hint: "


def _remapped(remaps: list[tuple[str, str]], pair: tuple[str, str]) -> list[tuple[str, str]]:
    """A later remapping of the same name replaces the earlier one, and comes last."""
    return [r for r in remaps if r[0] != pair[0]] + [pair]


def _with_conflict_hint(err: ParseError, path: Path) -> ParseError:
    """Malformed XML; say so when the cause is a git merge conflict left in the file."""
    try:
        lines = read_regular(path).decode(errors="replace").splitlines()
    except LimitError:
        return err
    markers = [i + 1 for i, line in enumerate(lines) if line.startswith(("<<<<<<<", ">>>>>>>"))]
    if markers:
        err.hint = (
            f"git conflict markers at line(s) {', '.join(map(str, markers))}: resolve the merge"
        )
    return err
