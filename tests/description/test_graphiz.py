"""urdf_to_graphiz: the ``.gv`` text against Debian's own (liburdfdom-tools), and the files
``belvedere run urdf urdf_to_graphiz`` writes."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

from belvedere.description.graphiz import urdf_to_graphiz
from belvedere.description.urdf import RobotModel
from tests.conftest import DATA, EXAMPLES

VALID = sorted((DATA / "urdf" / "check").glob("valid*.urdf"))
MBOT = EXAMPLES / "mbot_description" / "urdf" / "xacro" / "gazebo" / "mbot_gazebo.xacro"


def _theirs(urdf: Path, where: Path) -> str:
    tool = shutil.which("urdf_to_graphiz")
    if tool is None:
        pytest.skip("urdf_to_graphiz (Debian liburdfdom-tools) is not installed")
    subprocess.run([tool, str(urdf), "out"], cwd=where, capture_output=True, check=True, timeout=30)
    return (where / "out.gv").read_text()


@pytest.mark.oracle
@pytest.mark.parametrize("fixture", VALID, ids=lambda p: p.stem)
def test_same_gv_as_urdf_to_graphiz(fixture: Path, tmp_path: Path) -> None:
    assert urdf_to_graphiz(RobotModel.from_path(fixture)) == _theirs(fixture, tmp_path)


@pytest.mark.oracle
def test_turned_joints_print_their_rpy_as_urdfdom(tmp_path: Path) -> None:
    urdf = tmp_path / "turned.urdf"
    joints = [
        ("a", "0.1 0.2 0.3", "1.2 -0.4 2.9"),
        ("b", "1e-7 -3 12345.678", "0 1.5707963 0"),
        ("c", "0 0 0", "3.14159 0 -3.14159"),
        ("d", "0 0 0", "0 -1.5707963267948966 0.5"),
    ]
    body = "".join(
        f'<link name="{n}"/><joint name="j_{n}" type="fixed"><parent link="root"/>'
        f'<child link="{n}"/><origin xyz="{xyz}" rpy="{rpy}"/></joint>'
        for n, xyz, rpy in joints
    )
    urdf.write_text(f'<robot name="turned"><link name="root"/>{body}</robot>')
    assert urdf_to_graphiz(RobotModel.from_path(urdf)) == _theirs(urdf, tmp_path)


def test_run_writes_the_robots_gv_and_pdf(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    if shutil.which("dot") is None:
        pytest.skip("Graphviz's dot is not installed")
    monkeypatch.chdir(tmp_path)
    from belvedere.cli import main

    assert main(["run", "urdf", "urdf_to_graphiz", str(MBOT)]) == 0
    gv = (tmp_path / "mbot.gv").read_text()
    assert (tmp_path / "mbot.pdf").read_bytes().startswith(b"%PDF")
    model = RobotModel.from_path(MBOT)
    for link in model.links:
        assert f'"{link.name}" [label="{link.name}"];' in gv
    for joint in model.joints:
        assert f'"{joint.name}" -> "{joint.child}"' in gv


def test_run_without_a_file_says_how(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from belvedere.cli import main

    assert main(["run", "urdfdom", "urdf_to_graphiz"]) == 1
    assert "usage: urdf_to_graphiz input.xml [OUTPUT]" in capsys.readouterr().err
