"""What every verb prints besides its data, and ``-q``/``-v``, the same on every verb: the
course's robot (legacy unprefixed macro calls) gives one summary line, ``-v`` lists each call
with its file:line, ``-q`` hides the summary but no warning."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from belvedere.cli import main
from belvedere.description.xacro import Dialect, expand_file, process_file
from tests.conftest import EXAMPLES

GAZEBO = EXAMPLES / "mbot_description" / "urdf" / "xacro" / "gazebo"
MBOT = GAZEBO / "mbot_gazebo.xacro"
BASE = GAZEBO / "mbot_base_gazebo.xacro"
LAUNCH = EXAMPLES / "mbot_gazebo" / "launch" / "view_mbot_gazebo_empty_world.launch"

SUMMARY = (
    f"note: 8 legacy macro calls without the 'xacro:' prefix in {MBOT} and the files it "
    f"includes (expanded as ROS Melodic did); 'belvedere xacro --fix {MBOT}' rewrites them; "
    "-v lists them"
)
SITES = [
    f"{MBOT}:4:5: warning: deprecated macro call <mbot_base_gazebo>",
    f"{BASE}:153:13: warning: deprecated macro call <cylinder_inertial_matrix>",
    f"{BASE}:160:9: warning: deprecated macro call <wheel>",
    f"{BASE}:69:13: warning: deprecated macro call <cylinder_inertial_matrix>",
    f"{BASE}:161:9: warning: deprecated macro call <wheel>",
    f"{BASE}:163:9: warning: deprecated macro call <caster>",
    f"{BASE}:111:13: warning: deprecated macro call <sphere_inertial_matrix>",
    f"{BASE}:164:9: warning: deprecated macro call <caster>",
]
DIFF_DRIVE = f"{BASE}:168:13: note: diff-drive plugin 'differential_drive_controller'"

VERBS = {
    "xacro": ["xacro", str(MBOT)],
    "check": ["check", str(MBOT)],
    "display": ["display", str(MBOT), "--port", "0", "--duration", "0"],
    "sim": ["sim", str(MBOT), "--headless", "--rtf", "max", "--duration", "0.1"],
    "physics": ["sim", str(MBOT), "--engine", "physics", "--headless", "--duration", "0.01"],
    "launch": ["launch", str(LAUNCH), "--dump-params"],
}


def _summary(launch: bool) -> str:
    if not launch:
        return SUMMARY
    # the launch file names the robot through $(find mbot_description): an absolute path
    return SUMMARY.replace(str(MBOT), str(MBOT.resolve()))


def _deprecations(err: str) -> list[str]:
    return [line for line in err.splitlines() if "deprecated macro call" in line]


@pytest.mark.parametrize("verb", VERBS)
def test_legacy_calls_are_one_line_by_default(
    endpoint: str, verb: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(VERBS[verb]) == 0
    err = capsys.readouterr().err
    summary = _summary(verb == "launch")
    assert err.count(summary) == 1
    legacy = [line for line in err.replace("legacyMode", "").splitlines() if "legacy" in line]
    assert [line for line in legacy if "note:" in line] == [summary]
    assert _deprecations(err) == []


@pytest.mark.parametrize("verb", VERBS)
def test_quiet_hides_the_summary_on_every_verb(
    endpoint: str, verb: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["-q", *VERBS[verb]]) == 0
    err = capsys.readouterr().err
    assert "legacy" not in err.replace("legacyMode", "")
    assert _deprecations(err) == []
    assert "note:" not in err
    assert "simulated" not in err  # a notice, as the timing line is


@pytest.mark.parametrize("verb", VERBS)
def test_verbose_lists_every_call_with_its_place(
    endpoint: str, verb: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main([*VERBS[verb], "-v"]) == 0
    err = capsys.readouterr().err
    sites = SITES
    if verb == "launch":
        sites = [s.replace(str(MBOT), str(MBOT.resolve())) for s in SITES]
    assert [line.split(" without")[0] for line in _deprecations(err)] == sites
    assert "-v lists them" not in err


def test_quiet_keeps_warnings(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """-q hides notices — the course's swapped wheels that legacyMode turns back are fine as
    they are — not what is wrong (the same wheels without legacyMode turn the wrong way)."""
    assert main(["check", str(MBOT)]) == 0
    assert DIFF_DRIVE in capsys.readouterr().err
    assert main(["-q", "check", str(MBOT)]) == 0
    assert capsys.readouterr().err == ""
    base = Path(BASE)
    plain = tmp_path / base.name
    for sibling in base.parent.iterdir():
        text = sibling.read_text()
        if sibling == base:
            text = text.replace("<legacyMode>true</legacyMode>", "<legacyMode>false</legacyMode>")
        text = text.replace("$(find mbot_description)/urdf/xacro/gazebo/", "")  # the copies
        (tmp_path / sibling.name).write_text(text)
    top = tmp_path / MBOT.name
    assert main(["-q", "check", str(top)]) == 0
    err = capsys.readouterr().err
    assert err.startswith(f"{plain}:168:13: warning: diff-drive plugin")
    assert "or the robot turns the wrong way" in err
    assert err.count("\n") == 1
    assert main(["-qq", "check", str(top)]) == 0
    assert capsys.readouterr().err == ""


def test_summary_counts_keyword_tags_apart_and_one_call(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    src = tmp_path / "old.xacro"
    src.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <property name="w" value="1"/>\n'
        '  <macro name="box_link" params="n"><link name="${n}"/></macro>\n'
        '  <box_link n="a"/>\n'
        "</robot>\n"
    )
    assert main(["xacro", str(src)]) == 0
    assert capsys.readouterr().err == (
        f"note: 1 legacy macro call and 2 legacy xacro tags without the 'xacro:' prefix in "
        f"{src} (processed as ROS Melodic did); 'belvedere xacro --fix {src}' rewrites them; "
        "-v lists them\n"
    )
    assert main(["-v", "xacro", str(src)]) == 0
    err = capsys.readouterr().err.splitlines()
    assert [line.split(": warning: ")[0] for line in err] == [
        f"{src}:2:3",
        f"{src}:3:3",
        f"{src}:4:3",
    ]
    assert err[2].startswith(f"{src}:4:3: warning: deprecated macro call <box_link> without")


def test_the_fix_the_summary_names_rewrites_every_call_it_counted(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pkg = tmp_path / "mbot_description"
    shutil.copytree(EXAMPLES / "mbot_description", pkg)
    wrapper = pkg / "urdf" / "xacro" / "gazebo" / "mbot_gazebo.xacro"
    before = process_file(wrapper, dialect=Dialect.AUTO)
    assert main(["xacro", str(wrapper)]) == 0
    summary = capsys.readouterr().err
    command = re.search(r"'(belvedere xacro --fix [^']+)'", summary)
    assert command is not None
    assert main(command.group(1).split()[1:]) == 0
    fixed = capsys.readouterr().err.splitlines()
    assert len([line for line in fixed if ": fixed: <" in line]) == 8
    after = expand_file(wrapper, dialect=Dialect.MODERN)
    assert after.warnings == []
    assert after.to_xml() == before
    assert main(["xacro", str(wrapper)]) == 0
    assert capsys.readouterr().err == ""
