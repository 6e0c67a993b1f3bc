"""``belvedere check FILE [name:=value …]``: check_urdf's verdict and tree, plus a lint."""

from __future__ import annotations

import argparse
import json
import sys

from belvedere.cli._args import mappings_only
from belvedere.cli._report import report_diagnostics
from belvedere.description.checks import check_file, format_tree
from belvedere.description.xacro import Dialect
from belvedere.packages import PackageIndex

__all__ = ["add_parser", "run"]


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser(
        "check",
        parents=[common],
        help="check a URDF or xacro model (check_urdf, plus a physics lint)",
        description="Check a URDF or xacro file: urdfdom's verdict and link tree, then "
        "warnings about what misbehaves in simulation. Exit 0 clean, 1 on errors "
        "(or warnings with --strict).",
    )
    p.add_argument("input", metavar="FILE", help="URDF or xacro file")
    p.add_argument("--json", action="store_true", help="print a JSON report on stdout")
    p.add_argument(
        "--strict",
        action="store_true",
        help="warnings fail the check too, and files outside the model's package roots are "
        "not read",
    )
    p.add_argument(
        "--sim",
        dest="simulated",
        action="store_true",
        default=None,
        help="check as a model to simulate (default: if it has <gazebo> or <transmission>)",
    )
    p.add_argument(
        "--dialect",
        choices=[d.value for d in Dialect],
        default=Dialect.AUTO.value,
        help="xacro dialect for .xacro input (default: auto)",
    )
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    mappings = mappings_only(list(args.extra))
    packages = PackageIndex.from_environment(package_path=args.package_path, near=args.input)
    report = check_file(
        args.input,
        mappings=mappings,
        packages=packages,
        simulated=args.simulated,
        dialect=args.dialect,
        strict=args.strict,
    )
    if report.failure is not None and not args.json:
        raise report.failure  # printed as `belvedere xacro` prints it (trail, hint)
    if args.json:
        sys.stdout.write(json.dumps(report.to_json(), indent=2) + "\n")
    else:
        report_diagnostics(report.diagnostics, source=args.input)
        if report.model is not None:  # otherwise the errors above say why
            sys.stdout.write(format_tree(report.model))
    if not report.ok or (args.strict and report.warnings):
        return 1
    return 0
