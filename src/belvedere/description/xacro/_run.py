"""Running one xacro command: expand, list dependencies, check order, or fix."""

from __future__ import annotations

import logging
from dataclasses import dataclass

from belvedere.description.xacro._api import expand_file
from belvedere.description.xacro._command import XacroCommand
from belvedere.description.xacro._dialects import Dialect
from belvedere.description.xacro._errors import XacroError
from belvedere.description.xacro._fix import fix_file
from belvedere.packages import PackageIndex

__all__ = ["CommandResult", "run_command"]

logger = logging.getLogger("belvedere.xacro")


@dataclass(frozen=True, slots=True)
class CommandResult:
    text: str | None
    """What goes to stdout (or ``-o``); None when the command only reports."""
    exit_code: int = 0
    files: tuple[str, ...] = ()
    """The files an expansion read: the input, then what it included and loaded."""


def run_command(cmd: XacroCommand, *, packages: PackageIndex | None = None) -> CommandResult:
    """Run a parsed xacro command line."""
    if cmd.fix:
        changes = fix_file(
            cmd.input, mappings=cmd.mappings, packages=packages, root_dir=cmd.root_dir
        )
        for change in changes:
            logger.info("%s: fixed: <%s> -> <%s>", change.location, change.old, change.new)
        logger.info("%d tag(s) rewritten", len(changes))
        return CommandResult(None)
    if cmd.check_order:
        return _check_order(cmd, packages)
    expansion = expand_file(
        cmd.input,
        mappings=cmd.mappings,
        dialect=cmd.dialect,
        packages=packages,
        root_dir=cmd.root_dir,
        python2_floats=cmd.python2_floats,
        strict=cmd.strict,
    )
    files = (cmd.input, *dict.fromkeys(expansion.dependencies))
    if cmd.deps:
        return CommandResult(" ".join(dict.fromkeys(expansion.dependencies)), files=files)
    return CommandResult(expansion.to_xml(), files=files)


def _check_order(cmd: XacroCommand, packages: PackageIndex | None) -> CommandResult:
    def run(dialect: Dialect) -> str:
        return expand_file(
            cmd.input,
            mappings=cmd.mappings,
            dialect=dialect,
            packages=packages,
            root_dir=cmd.root_dir,
        ).to_xml()

    try:
        two_pass = run(Dialect.KINETIC)
    except XacroError as err:
        logger.warning("two-pass (kinetic) processing fails: %s", err.describe())
        two_pass = None
    in_order = run(Dialect.MELODIC)
    if two_pass == in_order:
        logger.info("%s: same result in-order and two-pass", cmd.input)
        return CommandResult(None)
    logger.warning(
        "%s: Document is incompatible to in-order processing: the results differ", cmd.input
    )
    return CommandResult(None, exit_code=1)
