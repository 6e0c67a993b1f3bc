"""ROS package discovery: ``$(find pkg)``, ``package://``, ``file://`` without ROS installed.

A package is a directory holding a ``package.xml``; the ``<name>`` inside wins over the folder
name. Directories are searched in this order, the first package of a name winning:

1. ``--package-path`` directories given by the user,
2. ``BELVEDERE_PACKAGE_PATH``, then ``ROS_PACKAGE_PATH`` (``os.pathsep``-separated),
3. the workspace of the input file: the package containing the file, and everything under
   that package's parent directory (a catkin ``src/``),
4. the packages belvedere provides itself (:data:`BUILTIN_PACKAGES`).

Each directory is crawled as rospack does: hidden directories are skipped, a package's
subdirectories are not searched, and a ``CATKIN_IGNORE`` or ``rospack_nosubdirs`` file stops
the descent.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Iterator, Mapping, Sequence
from pathlib import Path

from belvedere.errors import BelvedereError, ParseError, SourceLocation, did_you_mean
from belvedere.xmldom import parse_file

__all__ = ["PackageIndex", "PackageNotFoundError", "find_package_root", "read_package_name"]

_STOP_FILES = ("CATKIN_IGNORE", "COLCON_IGNORE", "AMENT_IGNORE", "rospack_nosubdirs")


class PackageNotFoundError(ParseError):
    """A package that no search directory holds."""


def read_package_name(package_xml: Path) -> str:
    """The ``<name>`` of a package manifest, or its folder's name if it declares none."""
    doc = parse_file(package_xml)
    for el in doc.root.elements():
        if el.tag == "name":
            name = el.text_content().strip()
            if name:
                return name
    return package_xml.parent.name


def find_package_root(path: Path) -> Path | None:
    """The nearest directory at or above ``path`` holding a ``package.xml``."""
    here = path if os.path.isdir(path) else path.parent
    for d in (here, *here.parents):
        if os.path.isfile(d / "package.xml"):
            return d
    return None


def _crawl(root: Path) -> Iterator[Path]:
    """Package directories under ``root``, in a stable (sorted) order."""
    stack = [root]
    while stack:
        d = stack.pop()
        try:
            entries = sorted(os.scandir(d), key=lambda e: e.name, reverse=True)
        except OSError:
            continue
        names = {e.name for e in entries}
        if "package.xml" in names:
            yield d
            continue
        if any(stop in names for stop in _STOP_FILES):
            continue
        for e in entries:
            if e.name.startswith(".") or not e.is_dir(follow_symlinks=True):
                continue
            stack.append(Path(e.path))


BUILTIN_PACKAGES = Path(__file__).resolve().parent / "share" / "packages"
"""Packages belvedere provides itself (xacro, gazebo_ros, robot_state_publisher, …): found
after everything on the search path, so a user's own copy wins."""


class PackageIndex:
    """Finds packages by name along a search path, crawling lazily and caching; then among
    the packages belvedere provides."""

    def __init__(self, search_path: Sequence[Path]) -> None:
        seen: set[Path] = set()
        self.search_path: list[Path] = []
        for p in search_path:
            resolved = p.expanduser().resolve()
            if resolved not in seen:
                seen.add(resolved)
                self.search_path.append(resolved)
        self._found: dict[str, Path] = {}
        self._crawled = 0  # how many search_path entries are indexed

    @classmethod
    def from_environment(
        cls,
        *,
        package_path: Iterable[str | Path] = (),
        near: str | Path | None = None,
        environ: Mapping[str, str] | None = None,
    ) -> PackageIndex:
        """The standard search path: options, environment, then the workspace of ``near``."""
        env = os.environ if environ is None else environ
        dirs = [Path(p) for p in package_path]
        for var in ("BELVEDERE_PACKAGE_PATH", "ROS_PACKAGE_PATH"):
            dirs.extend(Path(p) for p in env.get(var, "").split(os.pathsep) if p)
        if near is not None:
            dirs.extend(workspace_dirs(Path(near)))
        return cls(dirs)

    def with_workspace_of(self, file: str | Path) -> PackageIndex:
        """This index extended by the workspace of ``file`` (searched last)."""
        return PackageIndex([*self.search_path, *workspace_dirs(Path(file))])

    def _index_next(self) -> bool:
        if self._crawled >= len(self.search_path):
            return False
        root = self.search_path[self._crawled]
        self._crawled += 1
        for pkg in _crawl(root):
            try:
                name = read_package_name(pkg / "package.xml")
            except BelvedereError:
                name = pkg.name
            self._found.setdefault(name, pkg)
        return True

    def find(self, name: str, *, requested_at: SourceLocation | None = None) -> Path:
        """The directory of package ``name``; errors name every directory searched."""
        while name not in self._found:
            if not self._index_next():
                builtin = BUILTIN_PACKAGES / name
                if os.path.isfile(builtin / "package.xml"):
                    return builtin
                searched = (
                    "\n".join(f"    {d}" for d in self.search_path) or "    (nothing to search)"
                )
                msg = f"package {name!r} not found; searched:\n{searched}"
                hint = "add its parent directory with --package-path DIR, or set ROS_PACKAGE_PATH"
                near = did_you_mean(name, [*self._found, *builtin_package_names()])
                raise PackageNotFoundError(
                    msg, requested_at, hint=f"{near} Otherwise {hint}" if near else hint
                )
        return self._found[name]

    def packages(self, *, builtin: bool = False) -> dict[str, Path]:
        """Every package on the search path (crawls everything); with ``builtin``, then the
        packages belvedere provides that the path does not shadow, as :meth:`find` orders
        them (what rospack lists: every package installed)."""
        while self._index_next():
            pass
        found = dict(self._found)
        for name in builtin_package_names() if builtin else ():
            found.setdefault(name, BUILTIN_PACKAGES / name)
        return found

    def resolve_uri(self, uri: str, *, requested_at: SourceLocation | None = None) -> Path:
        """A ``package://pkg/rel``, ``file://abs`` or plain path, as a filesystem path."""
        if uri.startswith("package://"):
            rest = uri[len("package://") :]
            pkg, _, rel = rest.partition("/")
            if not pkg:
                msg = f"malformed package URI {uri!r}: expected package://PACKAGE/PATH"
                raise ParseError(msg, requested_at)
            root = self.find(pkg, requested_at=requested_at)
            return root / rel
        if uri.startswith("file://"):
            return Path(uri[len("file://") :])
        return Path(uri)


def builtin_package_names() -> list[str]:
    """The packages belvedere provides (:data:`BUILTIN_PACKAGES`)."""
    return sorted(p.parent.name for p in BUILTIN_PACKAGES.glob("*/package.xml"))


def workspace_dirs(file: Path) -> list[Path]:
    """The workspace of ``file``: its own package, then everything beside it (a catkin src/)."""
    pkg = find_package_root(file.resolve())
    if pkg is None:
        return []
    return [pkg, pkg.parent]
