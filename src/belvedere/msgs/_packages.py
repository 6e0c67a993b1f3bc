"""The message, service and action types of the packages on the package path, as catkin's
``add_message_files``/``add_service_files``/``add_action_files`` find them (``msg/*.msg``,
``srv/*.srv``, ``action/*.action``), read when a type of the package is first asked for.

No build step: a package's files are read and checked whole (every type a field names must
exist: built in, in the type store, in the package itself, or in another package on the
path, which is then read too), and parsed once per content.

Where packages are looked for, as a sourced ROS 1 workspace has them: ``--package-path``
directories a command adds, ``BELVEDERE_PACKAGE_PATH`` and ``ROS_PACKAGE_PATH`` (what
belvedere gives the scripts it runs), then the working directory's package and its catkin
workspace (``…/catkin_ws/src`` from anywhere inside ``catkin_ws``).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Final

from belvedere.bounded import DEFINITION_BYTES, read_regular_text
from belvedere.errors import SourceLocation, did_you_mean
from belvedere.msgs._genmsg import (
    Definition,
    InterfaceError,
    parse_action,
    parse_message,
    parse_service,
    store_type,
)
from belvedere.packages import PackageIndex, PackageNotFoundError, workspace_dirs

__all__ = ["KINDS", "Learned", "PackageInterfaces", "catkin_source_dirs"]

KINDS: Final = ("msg", "srv", "action")
"""The interface directories of a package, each holding files of its own suffix."""


@dataclass
class Learned:
    """What reading packages found: their message types (store names → definitions, in an
    order where each type's fields are defined before it) and their services."""

    definitions: dict[str, Definition] = field(default_factory=dict)
    services: set[str] = field(default_factory=set)
    packages: set[str] = field(default_factory=set)


def catkin_source_dirs(start: Path) -> list[Path]:
    """The ``src/`` of the catkin workspace ``start`` is in (a directory holding
    ``.catkin_workspace``, or a ``src/`` with catkin's top-level ``CMakeLists.txt``)."""
    here = start.resolve()
    for d in (here, *here.parents):
        src = d / "src"
        if os.path.isfile(d / ".catkin_workspace") or os.path.isfile(src / "CMakeLists.txt"):
            return [src] if os.path.isdir(src) else []
    return []


class PackageInterfaces:
    """The interface files of the packages along one package path."""

    def __init__(self, extra: Iterable[Path] = (), *, cwd: Path | None = None) -> None:
        self.extra = [Path(p) for p in extra]
        self.cwd = cwd
        self._index: PackageIndex | None = None

    def add_path(self, dirs: Iterable[Path]) -> None:
        """Search ``dirs`` too, before the environment's (a command's ``--package-path``, a
        launch's packages)."""
        new = [Path(d) for d in dirs if Path(d) not in self.extra]
        if new:
            self.extra.extend(new)
            self._index = None

    @property
    def index(self) -> PackageIndex:
        if self._index is None:
            here = self.cwd if self.cwd is not None else Path.cwd()
            env = PackageIndex.from_environment(package_path=self.extra)
            self._index = PackageIndex(
                [*env.search_path, *workspace_dirs(here), *catkin_source_dirs(here)]
            )
        return self._index

    def files(self, package: str) -> dict[str, list[Path]]:
        """``{"msg": [...], "srv": [...], "action": [...]}``: a package's interface files
        (empty when the path has no such package)."""
        try:
            home = self.index.find(package)
        except PackageNotFoundError:
            return {kind: [] for kind in KINDS}
        found: dict[str, list[Path]] = {}
        for kind in KINDS:
            folder = home / kind
            found[kind] = sorted(folder.glob(f"*.{kind}")) if folder.is_dir() else []
        return found

    def interfaces(self) -> dict[str, dict[str, list[str]]]:
        """Every package on the path that has interface files: its type names by kind
        (what ``rosmsg list``/``rospack`` would show of the user's own packages)."""
        out: dict[str, dict[str, list[str]]] = {}
        for package in sorted(self.index.packages()):
            files = self.files(package)
            if any(files.values()):
                out[package] = {kind: [p.stem for p in paths] for kind, paths in files.items()}
        return out

    def load(self, package: str, known: Callable[[str], bool]) -> Learned:
        """The types of ``package`` and of the packages on the path its types use (none when
        the path has no such package). ``known``: whether the type store has a type."""
        learned = Learned()
        self._load(package, known, learned)
        return learned

    def _load(self, package: str, known: Callable[[str], bool], learned: Learned) -> bool:
        if package in learned.packages:
            return True
        files = self.files(package)
        if not any(files.values()):
            return False
        learned.packages.add(package)
        own: dict[str, Definition] = {}
        for kind, paths in files.items():
            for path in paths:
                text = read_regular_text(path, limit=DEFINITION_BYTES, what="definition")
                for definition in _parse(kind, package, path.stem, str(path), text):
                    own[definition.name] = definition
                if kind == "srv":
                    learned.services.add(f"{package}/srv/{path.stem}")
        _check_cycles(own)
        learned.definitions.update(own)  # first: packages may use each other's types
        for definition in own.values():
            for used in definition.used_types():
                name = store_type(used.base)
                if known(name) or name in learned.definitions:
                    continue
                other = name.split("/", 1)[0]
                if self._load(other, known, learned) and name in learned.definitions:
                    continue
                raise _unknown(used.base, used.at, [*own, *learned.definitions])
        return True


def _parse(kind: str, package: str, base: str, path: str, text: str) -> list[Definition]:
    return list(_parse_cached(kind, package, base, path, text))


@lru_cache(maxsize=1024)
def _parse_cached(
    kind: str, package: str, base: str, path: str, text: str
) -> tuple[Definition, ...]:
    """Parsed once per content (a file read again, unchanged, costs no parse)."""
    if kind == "msg":
        return (parse_message(text, f"{package}/msg/{base}", path),)
    if kind == "srv":
        return parse_service(text, f"{package}/srv/{base}", path)
    return tuple(parse_action(text, package, base, path))


def _unknown(base: str, at: SourceLocation, candidates: Iterable[str]) -> InterfaceError:
    short = [f"{n.split('/')[0]}/{n.split('/')[-1]}" for n in candidates]
    hint = did_you_mean(base, short)
    if hint is None and "/" in base:
        hint = f"is package {base.split('/')[0]!r} on the package path (ROS_PACKAGE_PATH)?"
    return InterfaceError(f"unknown type {base!r}", at, hint=hint)


def _check_cycles(own: dict[str, Definition]) -> None:
    """A type that contains itself (through any chain of fields) is an error: genmsg's
    recursion would never end, and no message of it could be written."""
    state: dict[str, int] = {}  # 1: being visited, 2: done

    def visit(name: str, via: SourceLocation | None) -> None:
        if state.get(name) == 2:
            return
        if state.get(name) == 1:
            msg = f"type {name.replace('/msg/', '/')!r} contains itself"
            raise InterfaceError(msg, via, hint="a message cannot hold itself, even in an array")
        state[name] = 1
        for used in own[name].used_types():
            inner = store_type(used.base)
            if inner in own:
                visit(inner, used.at)
        state[name] = 2

    for name in own:
        visit(name, None)
