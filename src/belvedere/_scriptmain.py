"""A user's script as the main program of its process, as ``python3 script.py`` runs it.

The first code of every script belvedere runs (``launch``'s script nodes run it in a process
of their own; ``belvedere run SCRIPT`` in its own process, once the command line is read). It
imports only the standard library: the script's own imports come first, and belvedere's
message modules load only when the script asks for one.
"""

from __future__ import annotations

import atexit
import builtins
import contextlib
import importlib.abc
import importlib.util
import os
import sys
import threading
import types
from collections.abc import Sequence
from importlib.machinery import ModuleSpec
from typing import Any, NoReturn

__all__ = ["run_as_main"]


class _BelvedereMessages:
    """Finds ``std_msgs.msg`` and the like in belvedere's type store (:mod:`belvedere.ros1`),
    which loads only when an import finds nothing else: last on :data:`sys.meta_path`."""

    busy = False

    def find_spec(self, name: str, path: Sequence[str] | None, target: Any = None) -> Any:
        if self.busy:
            return None
        self.busy = True
        try:
            from belvedere.ros1._finder import install
        except ImportError:
            return None  # belvedere.ros1 itself is loading: its misses are not messages
        finally:
            self.busy = False
        sys.meta_path.remove(self)
        spec: ModuleSpec | None = install().find_spec(name, path, target)
        return spec


class _OpenCvWindows:
    """Gives OpenCV, when a script imports ``cv2``, belvedere's windows
    (:mod:`belvedere.ros1.highgui`): first on :data:`sys.meta_path`, it finds ``cv2`` where
    Python would and wraps its loader."""

    busy = False

    def find_spec(self, name: str, path: Sequence[str] | None, target: Any = None) -> Any:
        if name == "cv2.cv" and "cv2" in sys.modules and not self.busy:
            # OpenCV 2's constants module, which OpenCV 4 no longer has
            return importlib.util.spec_from_loader(name, _Legacy())
        if name != "cv2" or self.busy:
            return None

        self.busy = True
        try:
            spec = importlib.util.find_spec(name)
        finally:
            self.busy = False
        if spec is not None and spec.loader is not None:
            spec.loader = _Windowed(spec.loader)
        return spec


class _Windowed(importlib.abc.Loader):
    def __init__(self, loader: Any) -> None:
        self.loader = loader

    def create_module(self, spec: ModuleSpec) -> types.ModuleType | None:
        module: types.ModuleType | None = self.loader.create_module(spec)
        return module

    def exec_module(self, module: types.ModuleType) -> None:
        self.loader.exec_module(module)
        from belvedere.ros1.highgui import install

        # cv2's package replaces itself with its native module's contents while it loads
        install(sys.modules.get("cv2", module))


class _Legacy(importlib.abc.Loader):
    def create_module(self, spec: ModuleSpec) -> types.ModuleType:
        from belvedere.ros1.cv_legacy import legacy_module

        cv2 = sys.modules["cv2"]
        legacy = legacy_module(cv2)
        cv2.cv = legacy  # type: ignore[attr-defined]
        return legacy

    def exec_module(self, module: types.ModuleType) -> None:
        del module


def run_as_main(argv0: str, file: str, runnable: str, site: str, args: Sequence[str]) -> NoReturn:
    """Run ``runnable`` (the script, or its Python 3 form) as the script ``file`` would run
    as ``__main__``, and end the process with its exit status.

    As Python 3.9+ and rosrun run a script: ``__file__`` and tracebacks name ``file`` (an
    absolute path), ``sys.argv`` is ``argv0`` and ``args``, ``sys.path[0]`` is the script's
    real directory; belvedere's ROS modules (``site``) come next. A traceback starts at the
    script's own frame. The script's end is Python's (its threads joined, its exit functions
    run), then the process leaves without the interpreter's finalization, where Zenoh's
    threads, still delivering, would abort it.
    """
    sys.argv = [argv0, *args]
    sys.path[0:1] = [os.path.dirname(os.path.realpath(file)), site]
    sys.meta_path.append(_BelvedereMessages())
    sys.meta_path.insert(0, _OpenCvWindows())
    with open(runnable, "rb") as f:
        source = f.read()
    # The original is compiled as Python reads a file (its coding line); a translation is
    # UTF-8 text whatever the original's coding line says.
    code = compile(source if runnable == file else source.decode("utf-8"), file, "exec")
    main = types.ModuleType("__main__")
    main.__file__ = file
    main.__builtins__ = builtins  # type: ignore[attr-defined]
    sys.modules["__main__"] = main
    status = 0
    try:
        exec(code, main.__dict__)
    except SystemExit as end:
        if end.code is None or isinstance(end.code, int):
            status = end.code or 0
        else:
            sys.stderr.write(f"{end.code}\n")  # as Python prints a message it exits with
            status = 1
    except BaseException as error:  # noqa: BLE001 (the script's: printed as Python would)
        # From the script's own frame on, as Python prints it: this function's is not its.
        trace = error.__traceback__
        error.with_traceback(trace.tb_next if trace is not None else None)
        sys.excepthook(type(error), error, error.__traceback__)
        status = 130 if isinstance(error, KeyboardInterrupt) else 1
    threading._shutdown()  # type: ignore[attr-defined]
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(OSError, ValueError):  # a closed pipe, a closed stream
            stream.flush()
    os._exit(status)
