"""``$(…)`` substitutions: arg, find, env, optenv, dirname, cwd, eval."""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import Any

from belvedere.description.xacro._builtins import expose, math_functions, python_functions
from belvedere.description.xacro._errors import XacroError
from belvedere.description.xacro._interpreter import evaluate
from belvedere.description.xacro._symbols import Scope
from belvedere.errors import SourceLocation
from belvedere.packages import PackageIndex

__all__ = ["Substitutions"]


class Substitutions:
    """Resolves one ``$(…)`` at a time, against the run's args, packages and current file."""

    def __init__(
        self,
        *,
        args: dict[str, str],
        packages: PackageIndex,
        root_dir: str,
        current_file: Callable[[], str | None],
        here: Callable[[], SourceLocation | None],
    ) -> None:
        self.args = args
        """Shared with the processor: ``xacro:arg`` adds defaults to it."""
        self.packages = packages
        self.root_dir = root_dir
        self.current_file = current_file
        self.here = here
        self.found: list[str] = []
        """Every package directory ``$(find)`` resolved (the model's package roots)."""

    def __call__(self, inner: str) -> str:
        """The value of ``$(inner)``."""
        if inner == "cwd":
            return os.path.abspath(self.root_dir)
        if inner.startswith("eval ") or inner == "eval":
            return self._eval(inner[5:])
        words = [w for w in inner.split(" ") if w]
        if not words:
            msg = "empty substitution $()"
            raise XacroError(msg)
        cmd, args = words[0], words[1:]
        if cmd == "arg":
            self._expect(len(args) == 1, "$(arg NAME) takes exactly one name", inner)
            return self.arg(args[0])
        if cmd == "find":
            self._expect(len(args) == 1, "$(find PACKAGE) takes exactly one package name", inner)
            return self.find(args[0])
        if cmd == "env":
            self._expect(len(args) == 1, "$(env VAR) takes exactly one variable", inner)
            try:
                return os.environ[args[0]]
            except KeyError:
                msg = f"environment variable {args[0]} is not set"
                raise XacroError(msg, hint=f"use $(optenv {args[0]} DEFAULT)") from None
        if cmd == "optenv":
            self._expect(bool(args), "$(optenv VAR [DEFAULT]) needs a variable", inner)
            return os.environ.get(args[0], " ".join(args[1:]))
        if cmd == "dirname":
            return self.dirname()
        msg = f"unknown substitution command $({inner})"
        raise XacroError(msg, hint="valid commands: arg, find, env, optenv, dirname, eval, cwd")

    @staticmethod
    def _expect(ok: bool, usage: str, inner: str) -> None:
        if not ok:
            msg = f"{usage}: $({inner})"
            raise XacroError(msg)

    def arg(self, name: str) -> str:
        try:
            return self.args[name]
        except KeyError:
            msg = f"undefined substitution argument {name!r}"
            hint = f'declare <xacro:arg name="{name}" default="…"/> or pass {name}:=VALUE'
            raise XacroError(msg, hint=hint) from None

    def find(self, package: str) -> str:
        root = str(self.packages.find(package, requested_at=self.here()))
        self.found.append(root)
        return root

    def dirname(self) -> str:
        current = self.current_file()
        if not current:
            msg = "$(dirname) needs a file; the input is a string"
            raise XacroError(msg)
        return os.path.abspath(os.path.dirname(current))

    def _eval(self, expr: str) -> str:
        if "__" in expr:
            msg = "$(eval ...) may not contain double underscore expressions"
            raise XacroError(msg)
        return str(evaluate(expr, Scope(None, root=self._eval_names())))

    def _eval_names(self) -> dict[str, Any]:
        # xacro and roslaunch evaluate $(eval) with Python's builtins and math; we give the
        # bounded builtins of the expression interpreter.
        names: dict[str, Any] = python_functions()
        names.update(math_functions())
        names.update(
            {
                "true": True,
                "false": False,
                "arg": expose(lambda name: _auto_convert(self.arg(name)), "arg"),
                "env": expose(lambda name: os.environ[name], "env"),
                "optenv": expose(lambda name, default="": os.environ.get(name, default), "optenv"),
                "find": expose(self.find, "find"),
                "dirname": expose(self.dirname, "dirname"),
            }
        )
        for k, v in self.args.items():
            names.setdefault(k, _auto_convert(v))
        return names


def _auto_convert(value: str) -> Any:
    """roslaunch's ``auto`` typing of an arg inside ``$(eval)``."""
    try:
        return float(value) if "." in value else int(value)
    except ValueError:
        pass
    low = value.lower()
    if low in ("true", "false"):
        return low == "true"
    return value
