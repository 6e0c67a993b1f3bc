"""``belvedere xacro FILE [name:=value …]``: expand xacro to URDF on stdout (or ``-o``)."""

from __future__ import annotations

import argparse
import logging
import os
import sys
from pathlib import Path

from belvedere.cli._args import mappings_only
from belvedere.description.xacro import run_command
from belvedere.description.xacro._command import add_xacro_arguments, command_from_namespace
from belvedere.errors import BelvedereError
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
            _write_atomically(Path(cmd.output), result.text)
        else:
            sys.stdout.write(result.text)
            sys.stdout.flush()
    return result.exit_code


def _write_atomically(out: Path, text: str) -> None:
    """Write ``out`` whole or not at all (creating its directory, as xacro's ``-o`` does)."""
    import tempfile

    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=out.parent, prefix=f".{out.name}.", suffix=".tmp")
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, out)
    except OSError as err:
        msg = f"cannot write {out}: {err.strerror or err}"
        raise BelvedereError(msg) from None
