"""Run by Debian's /usr/bin/python3 (genmsg, genpy, the generated stock message modules and
actionlib_msgs' genaction): generates Python classes for the user packages a JSON request on
stdin names, as catkin would, and answers JSON on stdout with what genpy made of each type.
Not imported by the tests themselves.

Debian installs the stock packages' generated modules but not their .msg files; genmsg finds
those through a search path, so each stock type's file is written out from its module's
``_full_text`` (whose first part is the file's text).
"""

import importlib
import io
import json
import os
import subprocess
import sys
import tempfile
from typing import Any

from genpy.generator import MsgGenerator, SrvGenerator

GENACTION = "/usr/lib/actionlib_msgs/genaction.py"
SEPARATOR = "\n" + "=" * 80 + "\n"
STOCK = ("std_msgs", "actionlib_msgs", "geometry_msgs")


def write_stock(root: str) -> dict[str, list[str]]:
    paths: dict[str, list[str]] = {}
    for pkg in STOCK:
        module = importlib.import_module(f"{pkg}.msg")
        folder = os.path.join(root, pkg, "msg")
        os.makedirs(folder)
        for name in dir(module):
            cls = getattr(module, name)
            if isinstance(cls, type) and getattr(cls, "_type", "") == f"{pkg}/{name}":
                with open(os.path.join(folder, f"{name}.msg"), "w") as f:
                    f.write(cls._full_text.split(SEPARATOR)[0])
        paths[pkg] = [folder]
    return paths


def generate(packages: dict[str, str], root: str) -> str:
    search = write_stock(os.path.join(root, "stock"))
    out = os.path.join(root, "py")
    msg_files: dict[str, list[str]] = {}
    for pkg, home in packages.items():
        files = []
        for kind in ("msg", "action"):
            folder = os.path.join(home, kind)
            if os.path.isdir(folder):
                files += [os.path.join(folder, n) for n in sorted(os.listdir(folder))]
        made = os.path.join(root, "gen", pkg)
        for action in [f for f in files if f.endswith(".action")]:
            subprocess.run(
                [sys.executable, GENACTION, "-o", made, action],
                check=True,
                stdout=subprocess.DEVNULL,
            )
        msgs = [f for f in files if f.endswith(".msg")]
        if os.path.isdir(made):
            msgs += [os.path.join(made, n) for n in sorted(os.listdir(made))]
        msg_files[pkg] = msgs
        search[pkg] = sorted({os.path.dirname(f) for f in msgs})
    for pkg, home in packages.items():
        srv_dir = os.path.join(home, "srv")
        srvs = (
            [os.path.join(srv_dir, n) for n in sorted(os.listdir(srv_dir))]
            if os.path.isdir(srv_dir)
            else []
        )
        for kind, files, gen in (
            ("msg", msg_files[pkg], MsgGenerator()),
            ("srv", srvs, SrvGenerator()),
        ):
            folder = os.path.join(out, pkg, kind)
            os.makedirs(folder, exist_ok=True)
            if gen.generate_messages(pkg, files, folder, search) != 0:
                failed = f"genpy failed for {pkg}/{kind}"
                raise SystemExit(failed)
            with open(os.path.join(folder, "__init__.py"), "w") as f:
                for file in files:
                    base = os.path.basename(file).rsplit(".", 1)[0]
                    f.write(f"from ._{base} import *\n")
        with open(os.path.join(out, pkg, "__init__.py"), "w"):
            pass
    return out


def describe(cls: Any, data: str | None) -> dict[str, Any]:
    out = {
        "md5sum": cls._md5sum,
        "full_text": cls._full_text,
        "slots": list(cls.__slots__),
        "slot_types": list(cls._slot_types),
        "constants": {
            k: v
            for k, v in vars(cls).items()
            if not k.startswith("_") and isinstance(v, (int, float, str, bool))
        },
    }
    buff = io.BytesIO()
    cls().serialize(buff)
    out["default_bytes"] = buff.getvalue().hex()
    if data is not None:
        msg = cls().deserialize(bytes.fromhex(data))
        buff = io.BytesIO()
        msg.serialize(buff)
        out["bytes"] = buff.getvalue().hex()
        out["str"] = str(msg)
    return out


def main() -> None:
    request = json.load(sys.stdin)
    answer: dict[str, Any] = {}
    with tempfile.TemporaryDirectory() as root:
        sys.path.insert(0, generate(request["packages"], root))
        for name, data in request["messages"].items():
            pkg, kind, base = name.split("/")  # kind: msg, or srv for a service's halves
            module = importlib.import_module(f"{pkg}.{kind}")
            answer[name] = describe(getattr(module, base), data)
        for name in request["services"]:
            pkg, base = name.split("/")
            cls = getattr(importlib.import_module(f"{pkg}.srv"), base)
            answer[name] = {"md5sum": cls._md5sum, "type": cls._type}
    json.dump(answer, sys.stdout)


if __name__ == "__main__":
    main()
