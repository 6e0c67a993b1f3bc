"""turtlesim's types: their MD5 sums as Debian's genmsg computes them from the same .msg and
.srv text (written out here, as turtlesim's package has them), and what a script imports."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path
from typing import Any

import pytest

from belvedere.msgs._turtlesim_types import TURTLESIM_MESSAGES, TURTLESIM_SERVICES
from belvedere.ros1 import message_class, service_class
from tests.debian_ros import ROS_PYTHON, missing_debian_ros

# Debian's genmsg computes the sums from the files; genpy is not needed for that.
GENMSG_SUMS = """
import json, sys
from pathlib import Path
from typing import Any
import genmsg, genmsg.msg_loader, genmsg.gentools
root = Path(sys.argv[1])
ctx = genmsg.MsgContext.create_default()
out = {}
for path in sorted((root / "msg").glob("*.msg")):
    spec = genmsg.msg_loader.load_msg_from_file(ctx, str(path), "turtlesim/" + path.stem)
    ctx.register(spec.full_name, spec)
for path in sorted((root / "msg").glob("*.msg")):
    spec = ctx.get_registered("turtlesim/" + path.stem)
    out[spec.full_name] = genmsg.compute_md5(ctx, spec)
for path in sorted((root / "srv").glob("*.srv")):
    spec = genmsg.msg_loader.load_srv_from_file(ctx, str(path), "turtlesim/" + path.stem)
    out[spec.full_name] = genmsg.compute_md5(ctx, spec)
print(json.dumps(out))
"""


def _package(root: Path) -> None:
    (root / "msg").mkdir(parents=True)
    (root / "srv").mkdir()
    for name, text in TURTLESIM_MESSAGES.items():
        (root / "msg" / f"{name.rsplit('/', 1)[1]}.msg").write_text(text + "\n")
    for name, (req, res) in TURTLESIM_SERVICES.items():
        (root / "srv" / f"{name.rsplit('/', 1)[1]}.srv").write_text(f"{req}\n---\n{res}\n")


def test_md5_sums_match_debians_genmsg(tmp_path: Path) -> None:
    why = missing_debian_ros("genmsg")
    if why:
        pytest.skip(why)
    _package(tmp_path)
    run = subprocess.run(
        [str(ROS_PYTHON), "-c", GENMSG_SUMS, str(tmp_path)],
        capture_output=True,
        text=True,
        check=True,
    )
    want = json.loads(run.stdout)
    assert len(want) == 7
    got = {
        name: (
            service_class(name)
            if name.replace("/", "/srv/") in TURTLESIM_SERVICES
            else message_class(name)
        )._md5sum
        for name in want
    }
    assert got == want
    # the sums every ROS 1 turtlesim speaks with (a mismatch would refuse the connection)
    assert want["turtlesim/Pose"] == "863b248d5016ca62ea2e895ae5265cf9"
    assert want["turtlesim/Spawn"] == "0b2d2e872a8e2887d5ed626f2bf2c561"


def test_a_request_and_response_as_genpy_builds_them() -> None:
    spawn = service_class("turtlesim/Spawn")
    request: Any = spawn._request_class(1.0, 2.0, 0.5, "leo")
    assert (request.x, request.y, request.theta, request.name) == (1.0, 2.0, 0.5, "leo")
    assert spawn._response_class().__slots__ == ["name"]
    pose = message_class("turtlesim/Pose")()
    assert pose.__slots__ == ["x", "y", "theta", "linear_velocity", "angular_velocity"]
    assert message_class("turtlesim/Color")._slot_types == ["uint8", "uint8", "uint8"]
