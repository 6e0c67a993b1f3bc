"""dynamic_reconfigure's types: their MD5 sums as Debian's genmsg computes them from the same
definitions laid out as a ROS package (the oracle: ROS's own MD5 rules, constants included)."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path
from typing import Any

import pytest

from belvedere.msgs import _dynamic_reconfigure_types as dr
from belvedere.ros1 import message_class, service_class
from tests.debian_ros import ROS_PYTHON, missing_debian_ros

_ORACLE = """
import json, sys
import genmsg, genmsg.msg_loader as loader, genmsg.gentools as tools
root = sys.argv[1]
ctx = genmsg.MsgContext.create_default()
search = {"dynamic_reconfigure": [root + "/msg"]}
out = {}
for name in json.loads(sys.argv[2]):
    kind, base = name.split("/")[1:]
    path = f"{root}/{kind}/{base}.{kind}"
    full = f"dynamic_reconfigure/{base}"
    if kind == "msg":
        spec = loader.load_msg_from_file(ctx, path, full)
    else:
        spec = loader.load_srv_from_file(ctx, path, full)
    loader.load_depends(ctx, spec, search)
    out[name] = tools.compute_md5(ctx, spec)
print(json.dumps(out))
"""

WHY = missing_debian_ros("genmsg")


def _package(root: Path) -> None:
    """The definitions as ROS files: ``msg/*.msg`` and ``srv/*.srv``."""
    for kind, defs in (("msg", dr.MESSAGES), ("srv", dr.SERVICES)):
        (root / kind).mkdir()
        for name, text in defs.items():
            body = text if isinstance(text, str) else f"{text[0]}\n---\n{text[1]}"
            (root / kind / f"{name.split('/')[-1]}.{kind}").write_text(body + "\n")


@pytest.mark.skipif(WHY is not None, reason=WHY or "")
def test_md5_sums_match_genmsg(tmp_path: Path) -> None:
    _package(tmp_path)
    names = [*dr.MESSAGES, *dr.SERVICES]
    ran = subprocess.run(
        [str(ROS_PYTHON), "-c", _ORACLE, str(tmp_path), json.dumps(names)],
        capture_output=True,
        text=True,
        check=True,
    )
    want = json.loads(ran.stdout)
    for name in dr.MESSAGES:
        assert message_class(name)._md5sum == want[name], name
    for name in dr.SERVICES:
        assert service_class(name.replace("/srv/", "/"))._md5sum == want[name], name


def test_known_sums_and_constants() -> None:
    # The sums genmsg gives (test above): pinned so a change shows even without Debian ROS.
    assert message_class("dynamic_reconfigure/msg/Config")._md5sum == (
        "958f16a05573709014982821e6822580"
    )
    assert service_class("dynamic_reconfigure/Reconfigure")._md5sum == (
        "bb125d226a21982a4a98760418dc2672"
    )
    levels: Any = message_class("dynamic_reconfigure/msg/SensorLevels")
    assert (levels.RECONFIGURE_CLOSE, levels.RECONFIGURE_STOP) == (3, 1)
