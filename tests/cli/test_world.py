"""``belvedere world save`` against a simulation running in another process."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from belvedere.cli import main
from belvedere.graph import ZenohTransport
from belvedere.packages import PackageIndex
from belvedere.world import read_world
from tests.conftest import EXAMPLES
from tests.waiting import DEADLINE, wait_until

MBOT = str(EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_gazebo.xacro")
BELVEDERE = [sys.executable, "-m", "belvedere"]
PACKAGES = PackageIndex([EXAMPLES])
PLAYGROUND = str(EXAMPLES / "mbot_gazebo/worlds/playground.world")
SIM_ARGS = ["--engine", "physics", "--world", PLAYGROUND, "--headless", "-x", "0.5"]


def test_save_from_another_terminal(
    endpoint: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    sim = subprocess.Popen(  # paced, until we stop it
        [*BELVEDERE, "sim", MBOT, *SIM_ARGS],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    transport = ZenohTransport(endpoint=endpoint, serve_params=False)
    try:
        wait_until(
            lambda: "/gazebo/save_world" in transport.info(timeout=0.5).services,
            what="the simulation to offer /gazebo/save_world",
            detail=lambda: sim.poll(),
        )
        monkeypatch.chdir(tmp_path)  # a relative path is the tool's, not the simulation's
        assert main(["world", "save", "saved.world"]) == 0
        assert capsys.readouterr().out == f"{tmp_path / 'saved.world'}\n"
        saved = read_world(tmp_path / "saved.world", packages=PACKAGES)
        names = [m.name for m in saved.models]
        assert names == [m.name for m in read_world(PLAYGROUND, packages=PACKAGES).models] + [
            "mbot"
        ]
        mbot = saved.model("mbot")
        assert mbot is not None
        assert mbot.pose.xyz[0] == pytest.approx(0.5, abs=1e-3)
        assert main(["world", "save", str(tmp_path / "no/such/dir.world")]) == 1
        missing = tmp_path / "no/such/dir.world"
        assert capsys.readouterr().err.splitlines()[-1] == (
            f"error: cannot write {missing}: No such file or directory; nothing was written"
        )
    finally:
        transport.close()
        sim.terminate()
        sim.wait(timeout=DEADLINE)


def test_without_a_simulation_the_tool_says_so(
    endpoint: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["world", "save", str(tmp_path / "x.world")]) == 1
    err = capsys.readouterr().err
    assert (
        "error: no simulation is running on this graph (/gazebo/save_world is not offered)" in err
    )
    assert not (tmp_path / "x.world").exists()
