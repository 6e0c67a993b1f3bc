"""The user's compiled nodes: executables catkin built (``devel/lib/PKG/TYPE``,
``install/lib/PKG/TYPE``), found as rosrun finds them, and run against belvedere's ROS 1
master (:mod:`belvedere.ros1wire`).

Where catkin puts them: the workspace that holds the package's source (``<ws>/src/…/PKG`` →
``<ws>/devel/lib/PKG``, then ``<ws>/install/lib/PKG``), and every prefix of
``CMAKE_PREFIX_PATH`` (``<prefix>/lib/PKG``), which ``source devel/setup.bash`` sets."""

from __future__ import annotations

import os
import re
from pathlib import Path

__all__ = ["find_compiled", "is_compiled", "unbuilt_hint"]

_ELF = b"\x7fELF"


def _prefixes() -> list[Path]:
    return [Path(p) for p in os.environ.get("CMAKE_PREFIX_PATH", "").split(os.pathsep) if p]


def _workspaces(root: Path) -> list[Path]:
    """The directories above the package's that hold a catkin workspace's ``src``."""
    return [a for a in root.resolve().parents if (a / "src").is_dir()]


def find_compiled(root: Path, package: str, executable: str) -> Path | None:
    """The built ``executable`` of ``package`` (whose source is at ``root``), or None."""
    candidates = [
        ws / space / "lib" / package / executable
        for ws in _workspaces(root)
        for space in ("devel", "install")
    ]
    candidates += [prefix / "lib" / package / executable for prefix in _prefixes()]
    for path in candidates:
        if path.is_file() and os.access(path, os.X_OK):
            return path
    return None


def is_compiled(path: Path) -> bool:
    """Whether ``path`` is a program (ELF) rather than a script."""
    try:
        with path.open("rb") as f:
            return f.read(4) == _ELF
    except OSError:
        return False


def unbuilt_hint(root: Path, executable: str) -> str | None:
    """How to build ``executable`` when the package's CMakeLists.txt makes it and it is not
    built; None when the package does not make it."""
    cmake = root / "CMakeLists.txt"
    try:
        text = cmake.read_text(errors="replace")
    except OSError:
        return None
    made = re.search(rf"add_executable\s*\(\s*{re.escape(executable)}[\s)]", text)
    looped = re.search(rf"foreach\s*\([^)]*\b{re.escape(executable)}\b", text)
    if made is None and looped is None:
        return None
    workspaces = _workspaces(root)
    where = f" in {workspaces[0]}" if workspaces else ""
    return f"a C++ node of {cmake} that is not built: run catkin_make{where}"
