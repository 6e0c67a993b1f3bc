"""The layers of ARCHITECTURE.md hold: a lower package never imports a higher one.

Every module under ``src/belvedere`` is parsed (not imported) and each of its imports of
``belvedere`` — at module level and inside functions, ``TYPE_CHECKING`` ones too — is mapped
from the importing package to the imported one. A package may import the packages of the
layers below its own; within its layer, only the imports listed in :data:`SAME_LAYER`, which
the code already made when this table was written and which go one way (no circles). A
package the table does not know fails too: a new package takes a deliberate place here and
in ARCHITECTURE.md. Between modules, imports go one way too: no circles at all.
"""

from __future__ import annotations

import ast
import functools
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.conftest import REPO

SRC = REPO / "src" / "belvedere"

LAYERS: tuple[tuple[str, frozenset[str]], ...] = (
    (
        "foundations",
        frozenset(
            {
                "belvedere",  # the package itself: __version__
                "errors",
                "bounded",
                "locate",
                "fileio",
                "access",
                "xmldom",
                "yamlfile",
                "packages",
                "mappings",  # ROS's name:=value arguments (arrives with the runtime package)
            }
        ),
    ),
    ("data and models", frozenset({"msgs", "description", "world", "maps"})),
    ("the graph", frozenset({"graph", "tf"})),
    ("ROS 1's Python face and the scripts", frozenset({"ros1", "_scriptmain", "pyscripts"})),
    (
        "engines, tools and servers",
        frozenset({"nav", "sim", "teleop", "bags", "foxglove", "ros1wire", "viewer", "pictures"}),
    ),
    ("the ROS executables", frozenset({"nodes"})),
    ("roslaunch", frozenset({"launch"})),
    ("what the commands share", frozenset({"runtime"})),
    ("many runs", frozenset({"batch"})),
    ("the command line", frozenset({"cli"})),
    ("python -m belvedere", frozenset({"__main__"})),
)
"""Bottom first. A top-level module (``errors.py``) is a package of its own here."""

SAME_LAYER: frozenset[tuple[str, str]] = frozenset(
    {
        ("access", "errors"),
        ("bounded", "errors"),
        ("locate", "errors"),
        ("locate", "bounded"),
        ("fileio", "errors"),
        ("xmldom", "errors"),
        ("xmldom", "bounded"),
        ("yamlfile", "errors"),
        ("yamlfile", "bounded"),
        ("packages", "errors"),
        ("packages", "xmldom"),
        ("world", "description"),
        ("maps", "msgs"),
        ("tf", "graph"),
        ("pyscripts", "_scriptmain"),
        ("_scriptmain", "ros1"),
        ("viewer", "sim"),
    }
)
"""(importer, imported) within one layer: the imports the code made when the table was
written. Another is a decision: add it here only if it makes no circle."""


def layer_of(package: str) -> int:
    for index, (_, members) in enumerate(LAYERS):
        if package in members:
            return index
    msg = f"package {package!r} has no layer: give it one in tests/test_layers.py"
    raise AssertionError(msg + " and ARCHITECTURE.md")


def module_name(path: Path) -> tuple[str, ...]:
    """``src/belvedere/graph/_zenoh.py`` → ``("belvedere", "graph", "_zenoh")``."""
    parts = ("belvedere", *path.relative_to(SRC).with_suffix("").parts)
    return parts[:-1] if parts[-1] == "__init__" else parts


def package_of(module: tuple[str, ...]) -> str:
    """The package a module belongs to: the first name under ``belvedere`` (``belvedere``
    itself for the package's own ``__init__``)."""
    return module[1] if len(module) > 1 else "belvedere"


def imported_modules(path: Path, text: str) -> Iterator[tuple[int, str]]:
    """Every absolute module name the module at ``path`` (its source ``text``) imports, with
    its line, wherever the import is."""
    module = module_name(path)
    is_package = path.name == "__init__.py"
    for node in ast.walk(ast.parse(text, str(path))):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield node.lineno, alias.name
        elif isinstance(node, ast.ImportFrom):
            if node.level == 0:
                base = node.module or ""
            else:
                here = module if is_package else module[:-1]
                up = here[: len(here) - (node.level - 1)]
                base = ".".join([*up, *([node.module] if node.module else [])])
            yield node.lineno, base
            for alias in node.names:  # `from belvedere import graph`: a package by name
                yield node.lineno, f"{base}.{alias.name}"


def root_names() -> frozenset[str]:
    """The names ``belvedere/__init__.py`` itself defines (``__version__``)."""
    tree = ast.parse((SRC / "__init__.py").read_text(encoding="utf-8"))
    return frozenset(
        target.id
        for node in tree.body
        if isinstance(node, ast.Assign | ast.AnnAssign)
        for target in (node.targets if isinstance(node, ast.Assign) else [node.target])
        if isinstance(target, ast.Name)
    )


def imported_packages(path: Path, text: str) -> Iterator[tuple[int, str]]:
    """The belvedere packages a module imports (``from belvedere import __version__`` is the
    package itself)."""
    own = root_names()
    for line, name in imported_modules(path, text):
        parts = name.split(".")
        if parts[0] == "belvedere":
            yield line, "belvedere" if len(parts) == 1 or parts[1] in own else parts[1]


@functools.cache
def sources() -> dict[Path, str]:
    return {path: path.read_text(encoding="utf-8") for path in sorted(SRC.rglob("*.py"))}


@functools.cache
def real_imports() -> dict[tuple[str, str], list[str]]:
    return package_imports(sources())


def package_imports(modules: dict[Path, str]) -> dict[tuple[str, str], list[str]]:
    """(importer, imported) → where, for every import between two different packages."""
    found: dict[tuple[str, str], list[str]] = {}
    for path, text in modules.items():
        importer = package_of(module_name(path))
        for line, imported in imported_packages(path, text):
            if imported != importer:
                where = f"{path.relative_to(REPO)}:{line}"
                places = found.setdefault((importer, imported), [])
                if where not in places:  # `from belvedere import graph` names it twice
                    places.append(where)
    return found


def violations(imports: dict[tuple[str, str], list[str]]) -> list[str]:
    wrong = []
    for (importer, imported), places in sorted(imports.items()):
        if imported == "belvedere" and importer != "__main__":
            continue  # the package's own __init__ (the version) is below everything
        low, high = layer_of(imported), layer_of(importer)
        if low < high or (low == high and (importer, imported) in SAME_LAYER):
            continue
        side = "a higher layer" if low > high else "its own layer"
        wrong.append(
            f"{importer} ({LAYERS[high][0]}) imports {imported} ({side}: {LAYERS[low][0]})"
            f" at {', '.join(places)}"
        )
    return wrong


def test_every_package_has_a_layer() -> None:
    packages = {package_of(module_name(path)) for path in SRC.rglob("*.py")}
    for package in sorted(packages):
        layer_of(package)


def test_no_package_imports_a_higher_one() -> None:
    wrong = violations(real_imports())
    assert not wrong, "imports against the layers (see ARCHITECTURE.md):\n" + "\n".join(wrong)


def test_the_layers_are_disjoint() -> None:
    seen: dict[str, str] = {}
    for name, members in LAYERS:
        for package in members:
            assert package not in seen, f"{package} is in {seen[package]!r} and {name!r}"
            seen[package] = name


def test_same_layer_imports_make_no_circle() -> None:
    for importer, imported in SAME_LAYER:
        assert layer_of(importer) == layer_of(imported), (importer, imported)
    edges = SAME_LAYER

    def reaches(start: str, goal: str, seen: frozenset[str]) -> bool:
        return any(
            b == goal or (b not in seen and reaches(b, goal, seen | {b}))
            for a, b in edges
            if a == start
        )

    circles = sorted(f"{a} -> {b}" for a, b in edges if reaches(b, a, frozenset({b})))
    assert not circles, circles


def test_nothing_imports_the_command_line() -> None:
    importers = {a for (a, b) in real_imports() if b == "cli"}
    assert importers <= {"__main__"}, importers


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("from belvedere.cli import main\n", "graph (the graph) imports cli"),
        ("def f():\n    from belvedere.viewer import Viewer\n", "graph (the graph) imports viewer"),
        ("from ..launch import load_launch\n", "graph (the graph) imports launch"),
        ("from belvedere import nodes\n", "graph (the graph) imports nodes"),
        ("import belvedere.runtime.x as r\n", "graph (the graph) imports runtime"),
        ("from belvedere.tf import Buffer\n", "graph (the graph) imports tf (its own layer"),
    ],
)
def test_a_wrong_import_is_found(source: str, expected: str) -> None:
    """The checker itself: a module of ``graph`` that imports upwards, as a file would."""
    probe = SRC / "graph" / "_layers_probe.py"
    wrong = violations(package_imports({probe: source}))
    assert any(expected in line and "_layers_probe.py:" in line for line in wrong), wrong


def test_runtime_sits_between_launch_and_the_command_line() -> None:
    """``belvedere.runtime`` (what the commands share: running a session, the clock, hosting a
    script, joining a graph, a Foxglove bridge beside it) may use everything below the command
    line, and only the command line may use it."""
    session = SRC / "runtime" / "_session.py"
    below = "".join(
        f"from belvedere.{name} import x\n"
        for name in ("launch", "nodes", "graph", "foxglove", "viewer", "access", "packages")
    )
    assert violations(package_imports({session: below})) == []
    wrong = violations(package_imports({session: "from belvedere.cli._args import origin\n"}))
    assert [line.split(" at ")[0] for line in wrong] == [
        "runtime (what the commands share) imports cli (a higher layer: the command line)"
    ]
    cli = SRC / "cli" / "sim.py"
    assert violations(package_imports({cli: "from belvedere.runtime import run_session\n"})) == []
    for name in ("launch", "nodes", "viewer"):
        user = SRC / name / "_probe.py"
        assert violations(package_imports({user: "from belvedere.runtime import x\n"}))


def module_edges(modules: dict[Path, str]) -> dict[str, set[str]]:
    """Module → the belvedere modules it imports, anywhere in it. ``from pkg import _sub``
    names the submodule, not the package's face: that import does not run back up through
    ``pkg/__init__``'s own imports."""
    names = {".".join(module_name(path)) for path in modules}
    edges: dict[str, set[str]] = {}
    for path, text in modules.items():
        importer = ".".join(module_name(path))
        for node in ast.walk(ast.parse(text, str(path))):
            if isinstance(node, ast.Import):
                wanted = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = next(name for _, name in imported_modules(path, ast.unparse(node)))
                subs = [f"{base}.{alias.name}" for alias in node.names]
                wanted = subs if all(s in names for s in subs) else [base, *subs]
            else:
                continue
            for name in wanted:
                parts = name.split(".")
                while parts and ".".join(parts) not in names:
                    parts.pop()
                found = ".".join(parts)
                if found and found != importer:
                    edges.setdefault(importer, set()).add(found)
    return edges


def circles(edges: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected groups of more than one module (Tarjan's walk, iteratively)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
    for root in sorted(edges):
        if root in index:
            continue
        work = [(root, iter(sorted(edges.get(root, ()))))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, todo = work[-1]
            step = next(todo, None)
            if step is not None:
                if step not in index:
                    index[step] = low[step] = len(index)
                    stack.append(step)
                    on_stack.add(step)
                    work.append((step, iter(sorted(edges.get(step, ())))))
                elif step in on_stack:
                    low[node] = min(low[node], index[step])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                group = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    group.append(member)
                    if member == node:
                        break
                if len(group) > 1:
                    found.append(sorted(group))
    return found


def test_no_module_imports_itself_round_a_circle() -> None:
    """Between modules too, imports go one way: a writer takes the data it writes, a logger
    is handed its publisher, a panel gets the viewer's services through a Protocol."""
    found = circles(module_edges(sources()))
    assert not found, "import circles:\n" + "\n".join(" -> ".join(group) for group in found)


def test_a_circle_is_found() -> None:
    probe = {
        SRC / "graph" / "_a_probe.py": "from belvedere.graph import _b_probe\n",
        SRC / "graph" / "_b_probe.py": "def f():\n    from belvedere.graph._a_probe import x\n",
        SRC / "graph" / "__init__.py": "from belvedere.graph._a_probe import x\n",
    }
    assert circles(module_edges(probe)) == [
        ["belvedere.graph._a_probe", "belvedere.graph._b_probe"]
    ]
