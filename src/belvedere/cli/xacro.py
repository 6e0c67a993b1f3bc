"""``belvedere xacro FILE [name:=value …]``: expand xacro to URDF on stdout (or ``-o``)."""

from __future__ import annotations

import argparse
import logging
import sys

from belvedere.cli._args import mappings_only
from belvedere.description.xacro import run_command
from belvedere.description.xacro._command import add_xacro_arguments, command_from_namespace
from belvedere.fileio import write_file
from belvedere.packages import PackageIndex

logger = logging.getLogger("belvedere.cli")

__all__ = ["add_parser", "run"]


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser(
        "xacro",
        parents=[common],
        help="expand a xacro file to URDF",
        description="Expand a xacro file. Arguments name:=value set xacro args.",
    )
    add_xacro_arguments(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    mappings = mappings_only(list(args.extra))
    cmd = command_from_namespace(args, mappings)
    for notice in cmd.notices:
        logger.info("%s", notice)
    packages = PackageIndex.from_environment(package_path=args.package_path)
    result = run_command(cmd, packages=packages)
    if result.text is not None:
        if cmd.output:
            # Created with its directory, as xacro's -o does.
            write_file(cmd.output, result.text, make_dirs=True)
        else:
            sys.stdout.write(result.text)
            sys.stdout.flush()
    return result.exit_code
