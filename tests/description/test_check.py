"""`belvedere check`: urdfdom's verdict and tree (against Debian's check_urdf), and the lint."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest

from belvedere.cli import main
from belvedere.description.checks import check_file, format_tree
from tests.conftest import DATA, EXAMPLES

FIXTURES = sorted((DATA / "urdf" / "check").glob("*.urdf"))
MBOT = EXAMPLES / "mbot_description" / "urdf" / "xacro" / "gazebo" / "mbot_gazebo.xacro"


def test_fixture_set_covers_both_verdicts() -> None:
    names = [f.stem for f in FIXTURES]
    assert sum(n.startswith("valid") for n in names) >= 10
    assert sum(n.startswith("invalid") for n in names) >= 25


@pytest.mark.parametrize("fixture", FIXTURES, ids=lambda p: p.stem)
def test_expected_verdict(fixture: Path) -> None:
    report = check_file(fixture)
    assert report.ok == fixture.stem.startswith("valid"), [str(d) for d in report.diagnostics]
    if not report.ok:
        errors = report.errors
        assert errors
        assert errors[0].location is not None
        assert errors[0].location.path == str(fixture)


@pytest.mark.oracle
@pytest.mark.parametrize("fixture", FIXTURES, ids=lambda p: p.stem)
def test_same_verdict_and_tree_as_check_urdf(fixture: Path) -> None:
    tool = shutil.which("check_urdf")
    if tool is None:
        pytest.skip("check_urdf (Debian liburdfdom-tools) is not installed")
    ref = subprocess.run([tool, str(fixture)], capture_output=True, text=True, check=False)
    report = check_file(fixture)
    assert report.ok == (ref.returncode == 0), ref.stderr
    if report.ok:
        assert report.model is not None
        assert format_tree(report.model) == ref.stdout


@pytest.mark.oracle
def test_example_robot_tree_matches_check_urdf(tmp_path: Path) -> None:
    tool = shutil.which("check_urdf")
    if tool is None:
        pytest.skip("check_urdf (Debian liburdfdom-tools) is not installed")
    urdf = tmp_path / "mbot.urdf"
    assert main(["-q", "xacro", str(MBOT), "-o", str(urdf)]) == 0
    ref = subprocess.run([tool, str(urdf)], capture_output=True, text=True, check=True)
    report = check_file(MBOT)
    assert report.model is not None
    assert format_tree(report.model) == ref.stdout


def _messages(path: Path) -> list[str]:
    return [str(d) for d in check_file(path).diagnostics]


def test_seed_diff_drive_wheels_are_swapped_and_legacy_mode_compensates() -> None:
    report = check_file(MBOT)
    assert report.ok
    assert not [w for w in report.warnings if "diff-drive" in w.message]
    [warning] = [w for w in report.notes if "diff-drive" in w.message]  # fine as it is
    assert "leftJoint 'left_wheel_joint' is on the right (y = -0.19 m in base_footprint)" in (
        warning.message
    )
    assert "legacyMode is true, which compensates as Gazebo 7 did" in warning.message
    assert warning.location is not None
    assert warning.location.path.endswith("mbot_base_gazebo.xacro")


def write(tmp_path: Path, body: str) -> Path:
    path = tmp_path / "robot.urdf"
    path.write_text(f'<?xml version="1.0"?>\n<robot name="r">\n{body}</robot>\n')
    return path


INERTIA = '<inertia ixx="{}" ixy="0" ixz="0" iyy="{}" iyz="0" izz="{}"/>'


def inertial(mass: float, ixx: float, iyy: float, izz: float) -> str:
    return f'<inertial><mass value="{mass}"/>{INERTIA.format(ixx, iyy, izz)}</inertial>'


def test_lint_inertia(tmp_path: Path) -> None:
    body = (
        f'<link name="a">{inertial(0, 1, 1, 1)}</link>\n'
        f'<link name="b">{inertial(1, 1, 1, -1)}</link>\n'
        f'<link name="c">{inertial(1, 1, 1, 5)}</link>\n'
        '<joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>\n'
        '<joint name="ac" type="fixed"><parent link="a"/><child link="c"/></joint>\n'
    )
    text = "\n".join(_messages(write(tmp_path, body)))
    assert f"{tmp_path / 'robot.urdf'}:3:16: warning: link 'a': mass 0.0 is not positive" in text
    assert "link 'b': inertia tensor is not positive definite" in text
    assert "link 'c': principal moments 1, 1, 5 break the triangle inequality" in text


def test_lint_simulation_readiness(tmp_path: Path) -> None:
    body = (
        f'<link name="base">{inertial(1, 1, 1, 1)}'
        '<visual><geometry><mesh filename="missing.stl"/></geometry></visual></link>\n'
        '<link name="wheel"><collision><geometry><sphere radius="1"/></geometry>'
        "</collision></link>\n"
        '<joint name="j" type="revolute"><parent link="base"/><child link="wheel"/>'
        '<limit lower="1" upper="-1" effort="1" velocity="1"/></joint>\n'
        '<gazebo reference="whel"><mu1>1</mu1></gazebo>\n'
    )
    text = "\n".join(_messages(write(tmp_path, body)))
    assert "link 'wheel' has no <inertial>" in text
    assert "link 'base' has a visual but no collision" in text
    assert "mesh 'missing.stl' does not resolve: no file" in text
    assert "joint 'j': lower limit 1.0 > upper limit -1.0" in text
    assert '<gazebo reference="whel"> names no link or joint' in text


def test_simulation_warnings_only_for_simulated_models(tmp_path: Path) -> None:
    body = '<link name="a"><visual><geometry><sphere radius="1"/></geometry></visual></link>\n'
    path = write(tmp_path, body)
    assert check_file(path).warnings == []
    assert check_file(path, simulated=True).warnings == []  # a massless frame link is fine
    body = '<link name="a"><collision><geometry><sphere radius="1"/></geometry></collision>'
    body += "</link>\n"
    assert "no <inertial>" in str(check_file(write(tmp_path, body), simulated=True).warnings[0])


def test_zero_links_hints_at_legacy_xacro(tmp_path: Path) -> None:
    report = check_file(MBOT, dialect="modern")
    assert not report.ok
    assert any("try --dialect melodic" in e.message for e in report.errors)


def test_cli_exit_codes_and_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", str(MBOT)]) == 0
    out = capsys.readouterr()
    assert out.out.startswith("robot name is: mbot\n")
    assert "note: diff-drive plugin" in out.err
    assert main(["check", "--strict", str(MBOT)]) == 1
    capsys.readouterr()
    assert main(["check", "--json", str(MBOT)]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["ok"] is True
    assert data["root"] == "base_footprint"
    assert data["tree"]["children"][0]["link"] == "base_link"
    assert any(d["message"].startswith("diff-drive") for d in data["diagnostics"])
    bad = DATA / "urdf" / "check" / "invalid_two_roots.urdf"
    assert main(["check", str(bad)]) == 1
    err = capsys.readouterr().err
    assert f"{bad}:2:1: error: two root links found: [a] and [b]" in err
    assert main(["check", "--json", str(bad)]) == 1
    assert json.loads(capsys.readouterr().out)["ok"] is False


def test_check_takes_xacro_args(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", str(MBOT), "unused:=1"]) == 0
    assert main(["check", str(MBOT), "stray"]) == 1
    assert "name:=value" in capsys.readouterr().err


VARIANTS = ["mbot_gazebo", "mbot_gazebo_modern"] + [
    f"mbot_with_{s}_gazebo" for s in ("camera", "kinect", "laser")
]


@pytest.mark.parametrize("variant", VARIANTS)
def test_example_variants_check_clean_except_expected_warnings(variant: str) -> None:
    report = check_file(MBOT.with_name(f"{variant}.xacro"))
    assert report.ok
    unexpected = [
        str(w)
        for w in report.warnings
        if "deprecated macro call" not in w.message and "diff-drive plugin" not in w.message
    ]
    assert unexpected == []


def test_sensor_variants_carry_their_sensors() -> None:
    from belvedere.description.meshes import load_mesh, resolve_mesh_path
    from belvedere.description.urdf import Mesh, RobotModel

    sensors = {}
    for kind in ("camera", "kinect", "laser"):
        model = RobotModel.from_path(MBOT.with_name(f"mbot_with_{kind}_gazebo.xacro"))
        [sensor] = [s for g in model.gazebo for s in g.sensors]
        sensors[kind] = sensor
        if kind == "kinect":
            geometry = model.link("kinect_link").visuals[0].geometry
            assert isinstance(geometry, Mesh)
            mesh = load_mesh(resolve_mesh_path(geometry.filename, relative_to=model.path))
            assert mesh.bounds.ravel().tolist() == pytest.approx(
                [-0.032, -0.14, -0.019, 0.032, 0.14, 0.019]
            )
    assert sensors["camera"].attr("type") == "camera"
    assert sensors["kinect"].attr("type") == "depth"
    laser = sensors["laser"]
    assert laser.attr("type") == "ray"
    scan = laser.child("ray")
    assert scan is not None
    horizontal = scan.child("scan")
    assert horizontal is not None
    assert horizontal.child("horizontal") is not None
    plugin = laser.child("plugin")
    assert plugin is not None
    # relative: /scan under the root namespace, /robot_i/scan spawned in <group ns="robot_i">
    assert plugin.child_text("topicName") == "scan"


@pytest.mark.parametrize(
    ("body", "expected"),
    [
        (
            '<link name="a"><inertial><mass value="1"/>'
            '<inertia ixx="1" ixy="0" ixz="1e309" iyy="1" iyz="0" izz="1"/></inertial></link>\n',
            ":3:16: error: link [a] inertial: inertia ixz [1e309] is too large for a double "
            "(the limit is ±1.7976931348623157e+308)",
        ),
        (
            '<link name="a"/><link name="b"/>\n<joint name="j" type="fixed"><parent link="a"/>'
            '<child link="b"/><origin rpy="1e309 0 0"/></joint>\n',
            ":4:1: error: malformed origin for joint [j]: joint [j] origin rpy: component "
            "[1e309] of [1e309 0 0] is too large for a double",
        ),
        (
            '<link name="a"><visual><geometry><sphere radius="1e999"/></geometry></visual>'
            "</link>\n",
            ":3:16: error: link [a] visual: sphere radius [1e999] is too large for a double",
        ),
        (
            '<material name="m"><color rgba="1 1 1e400 1"/></material><link name="a"/>\n',
            ":3:20: error: material [m] color: material [m] color rgba: component [1e400]",
        ),
    ],
    ids=["inertia", "joint-origin", "visual", "colour"],
)
def test_numbers_too_large_for_a_double_are_one_error(
    endpoint: str, tmp_path: Path, capsys: pytest.CaptureFixture[str], body: str, expected: str
) -> None:
    path = write(tmp_path, body)
    assert main(["check", str(path)]) == 1
    out = capsys.readouterr()
    assert out.err == f"{path}{expected}" + out.err.split(expected, 1)[1]
    assert out.err.count("error:") == 1
    assert "Traceback" not in out.err
    assert out.out == ""
    # The simulators read the same model: the same error, before anything runs.
    for verb in (["sim", "--headless"], ["display"]):
        assert main([*verb, str(path), "--duration", "0.1"]) == 1
        err = capsys.readouterr().err
        assert err.startswith(f"{path}{expected}")
        assert "Traceback" not in err


def test_lint_survives_inertia_near_the_largest_double(tmp_path: Path) -> None:
    body = f'<link name="a">{inertial(1, 1e308, 1e308, 1e308)}</link>\n'
    body = body.replace('ixy="0"', 'ixy="1e308"')
    text = "\n".join(_messages(write(tmp_path, body)))
    assert "link 'a': inertia tensor is not positive definite" in text


def test_diff_drive_wheel_on_a_cycle_apart_from_the_tree(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    body = (
        '<link name="base"/><link name="a"/><link name="b"/>\n'
        '<joint name="left" type="continuous"><parent link="a"/><child link="b"/></joint>\n'
        '<joint name="right" type="continuous"><parent link="b"/><child link="a"/></joint>\n'
        '<gazebo><plugin name="dd" filename="libgazebo_ros_diff_drive.so">'
        "<leftJoint>left</leftJoint><rightJoint>right</rightJoint></plugin></gazebo>\n"
    )
    path = write(tmp_path, body)
    assert main(["check", "--strict", str(path)]) == 1
    err = capsys.readouterr().err
    assert (
        f"{path}:3:20: warning: links 'a', 'b' cannot be reached from the root link 'base': "
        "their joints form a cycle apart from the tree"
    ) in err
    assert (
        f"{path}:6:9: warning: diff-drive plugin 'dd': leftJoint 'left' is not connected to "
        "the root link 'base', so it cannot drive the robot"
    ) in err
    assert "Traceback" not in err


def test_lint_non_unit_axis(tmp_path: Path) -> None:
    limit = '<limit lower="0" upper="1" effort="1" velocity="1"/>'
    body = (
        '<link name="a"/><link name="b"/><link name="c"/><link name="d"/>\n'
        '<joint name="slide" type="prismatic"><parent link="a"/><child link="b"/>'
        f'<axis xyz="0 0 2"/>{limit}</joint>\n'
        '<joint name="turn" type="continuous"><parent link="b"/><child link="c"/>'
        '<axis xyz="1 1 0"/></joint>\n'
        '<joint name="near" type="continuous"><parent link="c"/><child link="d"/>'
        '<axis xyz="0.707 0 0.707"/></joint>\n'
    )
    text = "\n".join(_messages(write(tmp_path, body)))
    path = tmp_path / "robot.urdf"
    assert (
        f"{path}:4:1: warning: joint 'slide': axis 0 0 2 has length 2, not 1: "
        "robot_state_publisher (KDL) and simulators use the unit axis 0 0 1, so a prismatic "
        "joint at q moves q metres"
    ) in text
    assert f"{path}:5:1: warning: joint 'turn': axis 1 1 0 has length 1.41421" in text
    assert "'near'" not in text
