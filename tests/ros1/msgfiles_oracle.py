"""Run by Debian's /usr/bin/python3. ``write DIR``: writes the .msg and .srv files of
Debian's generated message modules (their definitions, kept in each class's ``_full_text``)
as a ROS package tree under DIR, so that Debian's own rosmsg and rossrv can read them (Debian
ships the modules but not the files). ``run``: runs Debian's rosmsg/rossrv once per command
line of the JSON list on stdin (in one process: a process each would take minutes) and
answers each one's output and exit status as JSON. Not imported by the tests themselves."""

import contextlib
import importlib
import io
import json
import pkgutil
import sys
from pathlib import Path

PACKAGES = (
    "actionlib_msgs",
    "geometry_msgs",
    "nav_msgs",
    "rosgraph_msgs",
    "sensor_msgs",
    "std_msgs",
    "std_srvs",
    "tf2_msgs",
    "trajectory_msgs",
    "visualization_msgs",
    "diagnostic_msgs",
)
SEPARATOR = "=" * 80


def own_text(full_text: str) -> str:
    """The type's own definition: what comes before the first dependency's section."""
    return full_text.split(SEPARATOR + "\n", 1)[0]


def write_file(root: Path, pkg: str, kind: str, name: str, text: str) -> None:
    folder = root / pkg
    (folder / kind).mkdir(parents=True, exist_ok=True)
    (folder / "package.xml").write_text(
        f'<package format="2"><name>{pkg}</name><version>0.0.0</version>'
        "<description>oracle</description><maintainer email='a@b.c'>a</maintainer>"
        "<license>BSD</license></package>\n"
    )
    (folder / kind / f"{name}.{kind}").write_text(text)


def run() -> None:
    import rosmsg  # type: ignore[import-not-found]

    answers = []
    for argv in json.load(sys.stdin):
        out = io.StringIO()
        code = 0
        sys.argv = argv
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
            try:
                rosmsg.rosmsgmain(rosmsg.MODE_SRV if argv[0] == "rossrv" else rosmsg.MODE_MSG)
            except SystemExit as exc:
                code = exc.code if isinstance(exc.code, int) else 1
        answers.append([out.getvalue(), code])
    json.dump(answers, sys.stdout)


def write(root: Path) -> None:
    for pkg in PACKAGES:
        for kind in ("msg", "srv"):
            try:
                module = importlib.import_module(f"{pkg}.{kind}")
            except ImportError:
                continue
            for info in pkgutil.iter_modules(module.__path__):
                if not info.name.startswith("_"):
                    continue
                cls = getattr(module, info.name[1:])
                if kind == "msg":
                    text = own_text(cls._full_text)
                else:
                    request = own_text(cls._request_class._full_text)
                    response = own_text(cls._response_class._full_text)
                    text = f"{request}---\n{response}"
                write_file(root, pkg, kind, info.name[1:], text)


if sys.argv[1] == "write":
    write(Path(sys.argv[2]))
else:
    run()
