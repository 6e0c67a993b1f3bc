"""What ``belvedere msg`` and ``belvedere srv`` share: rosmsg's and rossrv's actions over the
type store (:mod:`belvedere.ros1._show`), no graph needed."""

from __future__ import annotations

import argparse
import sys

from belvedere.ros1 import Kind, md5_text, package_types, show_text, type_names, type_packages

__all__ = ["add_type_parser"]


def add_type_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser],
    common: argparse.ArgumentParser,
    kind: Kind,
) -> None:
    word = {"msg": "message", "srv": "service"}[kind]
    p = sub.add_parser(
        kind, parents=[common], help=f"show {word} types, as ros{kind} does (no graph needed)"
    )
    actions = p.add_subparsers(dest="action", metavar="ACTION", required=True)

    def action(name: str, help_text: str) -> argparse.ArgumentParser:
        return actions.add_parser(name, parents=[common], help=help_text)

    for name, text in (
        ("show", f"a {word} type's fields, nested types indented"),
        ("info", "the same as show"),
    ):
        show = action(name, text)
        show.add_argument("type", help=f"pkg/Type, or Type alone: each package's {word} so named")
        show.add_argument(
            "-r", "--raw", action="store_true", help="the definition itself (without its comments)"
        )
    action("list", f"every {word} type known")
    action("md5", f"a {word} type's MD5 sum").add_argument("type")
    action("package", f"the {word} types of a package").add_argument("package")
    action("packages", f"the packages that hold {word} types")
    p.set_defaults(run=lambda args: run(args, kind))


def run(args: argparse.Namespace, kind: Kind) -> int:
    action = args.action
    if action in ("show", "info"):
        out = show_text(kind, args.type, raw=args.raw)
    elif action == "md5":
        out = md5_text(kind, args.type)
    elif action == "package":
        out = "\n".join(package_types(kind, args.package)) + "\n"
    elif action == "packages":
        out = "\n".join(type_packages(kind)) + "\n"
    else:
        out = "\n".join(type_names(kind)) + "\n"
    sys.stdout.write(out)
    return 0
