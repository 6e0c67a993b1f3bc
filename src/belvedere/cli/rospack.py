"""``belvedere rospack find|list|depends|depends1 …``: what rospack answers, over belvedere's
package path (``--package-path``, ``BELVEDERE_PACKAGE_PATH``, ``ROS_PACKAGE_PATH``), then the
packages belvedere provides (turtlesim, amcl, gazebo_ros …): they are installed with it, as
ROS's are with ROS, and found after the path as ``$(find)`` finds them."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from belvedere.errors import BelvedereError
from belvedere.packages import PackageIndex
from belvedere.xmldom import parse_file

__all__ = ["add_parser", "run"]

DEPENDENCY_TAGS = (
    "depend",
    "build_export_depend",
    "buildtool_export_depend",
    "exec_depend",
    "run_depend",
)
"""What rospack follows: the dependencies a package needs to run (format 2's depend,
build_export_depend, buildtool_export_depend and exec_depend; format 1's run_depend)."""


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser(
        "rospack",
        parents=[common],
        help="find packages and their dependencies, as rospack",
        description="rospack find PKG | list | list-names | depends PKG | depends1 PKG",
    )
    p.add_argument("command", choices=["find", "list", "list-names", "depends", "depends1"])
    p.add_argument("package", nargs="?", help="the package (find, depends, depends1)")
    p.set_defaults(run=run)


def direct_dependencies(root: Path) -> list[str]:
    """A package's dependencies as its package.xml lists them, first mention first."""
    package = parse_file(root / "package.xml").first_element()
    names: list[str] = []
    for element in package.elements() if package is not None else ():
        if element.tag in DEPENDENCY_TAGS:
            name = element.text_content().strip()
            if name and name not in names:
                names.append(name)
    return names


def all_dependencies(packages: PackageIndex, name: str) -> list[str]:
    """Every package ``name`` depends on, each after its own dependencies. A dependency that
    is no package on the path is a system dependency (a rosdep key), left out as rospack
    leaves it out."""
    order: list[str] = []
    visiting: set[str] = set()

    def visit(pkg: str) -> None:
        if pkg in order or pkg in visiting:
            return
        visiting.add(pkg)
        try:
            root = packages.find(pkg)
        except BelvedereError:
            return
        for dep in direct_dependencies(root):
            visit(dep)
        visiting.discard(pkg)
        order.append(pkg)

    for dep in direct_dependencies(packages.find(name)):
        visit(dep)
    return order


def _known(packages: PackageIndex, names: list[str]) -> list[str]:
    out = []
    for name in names:
        try:
            packages.find(name)
        except BelvedereError:
            continue
        out.append(name)
    return out


def run(args: argparse.Namespace) -> int:
    packages = PackageIndex.from_environment(package_path=args.package_path)
    needs_package = args.command in ("find", "depends", "depends1")
    if needs_package and not args.package:
        msg = f"rospack {args.command} needs a package name"
        raise BelvedereError(msg)
    if args.command == "find":
        sys.stdout.write(f"{packages.find(args.package)}\n")
    elif args.command in ("list", "list-names"):
        found = sorted(packages.packages(builtin=True).items())
        if args.command == "list":
            sys.stdout.write("".join(f"{name} {path}\n" for name, path in found))
        else:
            sys.stdout.write("".join(f"{name}\n" for name, _ in found))
    elif args.command == "depends1":
        root = packages.find(args.package)
        direct = _known(packages, direct_dependencies(root))
        sys.stdout.write("".join(f"{d}\n" for d in direct))
    else:
        sys.stdout.write("".join(f"{d}\n" for d in all_dependencies(packages, args.package)))
    return 0
