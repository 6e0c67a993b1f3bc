"""The xacro processor: modern xacro 2.1.1, byte for byte, plus the legacy ROS 1 dialects.

Entry points:

- :func:`process_file` / :func:`process_string` return the URDF (or SDF) text.
- :func:`expand_file` returns an :class:`Expansion`: the expanded document, whose elements keep
  the xacro file and line that produced them, with the warnings and the files read.
- :func:`run_command` runs a xacro command line (``belvedere xacro``, or ``xacro --inorder
  FILE args`` as launch files write it, parsed by :func:`parse_xacro_command`).

The default dialect ``auto`` gives modern results, except that legacy unprefixed tags and
macro calls (which modern xacro silently leaves unexpanded) are expanded with a warning.
"""

from belvedere.description.xacro._api import (
    Expansion,
    expand_file,
    expand_string,
    process_file,
    process_string,
)
from belvedere.description.xacro._command import (
    XacroCommand,
    is_xacro_program,
    parse_xacro_argv,
    parse_xacro_command,
)
from belvedere.description.xacro._dialects import Dialect, XacroWarning, legacy_summary
from belvedere.description.xacro._errors import XacroError
from belvedere.description.xacro._run import CommandResult, run_command

__all__ = [
    "CommandResult",
    "Dialect",
    "Expansion",
    "XacroCommand",
    "XacroError",
    "XacroWarning",
    "expand_file",
    "expand_string",
    "is_xacro_program",
    "legacy_summary",
    "parse_xacro_argv",
    "parse_xacro_command",
    "process_file",
    "process_string",
    "run_command",
]
