"""cv_bridge against Debian's python3-cv-bridge, as a matrix: the same script
(``cv_bridge_cases.py``: every encoding sensor_msgs defines to every other, generated images,
messages' bytes, step and endianness, compressed images, the errors) prints the same under
both."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path
from typing import Any

import pytest

from belvedere.pyscripts import script_command
from tests.debian_ros import ROS_PYTHON, missing_debian_ros

CASES = Path(__file__).with_name("cv_bridge_cases.py")


def _run(command: list[str]) -> dict[str, Any]:
    done = subprocess.run(command, capture_output=True, text=True, timeout=300, check=False)
    assert done.returncode == 0, done.stderr[-3000:]
    result: dict[str, Any] = json.loads(done.stdout)
    return result


def test_cv_bridge_converts_as_debians_does() -> None:
    why = missing_debian_ros("cv_bridge, cv2, sensor_msgs.msg")
    if why:
        pytest.skip(f"{why} (python3-cv-bridge)")
    theirs = _run([str(ROS_PYTHON), str(CASES)])
    ours = _run(script_command(CASES))
    assert len(theirs) > 900
    differ = {k: (theirs[k], ours.get(k)) for k in theirs if theirs[k] != ours.get(k)}
    assert not differ
    assert ours.keys() == theirs.keys()
