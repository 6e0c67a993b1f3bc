"""``belvedere msg``/``srv`` against Debian's ``rosmsg``/``rossrv`` line for line, for every
standard type both know: ``show`` (nested, constants), ``show -r`` (but for comments, which
the type store does not keep), ``md5``, ``package``, a type named without its package.

Debian ships the generated message modules but not the ``.msg`` files rosmsg reads:
``msgfiles_oracle.py`` writes them back from the modules' definitions, then runs Debian's
rosmsg on them. Skipped where Debian's rosmsg is absent."""

from __future__ import annotations

import json
import os
import re
import subprocess
from collections.abc import Sequence
from pathlib import Path

import pytest

from belvedere.cli import main
from belvedere.ros1._show import Kind, type_names
from tests.debian_ros import ROS_PYTHON

pytestmark = [pytest.mark.oracle, pytest.mark.usefixtures("pristine_types")]

ROSMSG = Path("/usr/bin/rosmsg")
SCRIPT = Path(__file__).with_name("msgfiles_oracle.py")


class Rosmsg:
    """Debian's rosmsg and rossrv over the definitions of Debian's message modules."""

    def __init__(self, root: Path) -> None:
        self.env = {**os.environ, "ROS_PACKAGE_PATH": str(root)}

    def __call__(self, lines: Sequence[Sequence[str]]) -> list[tuple[str, int]]:
        done = subprocess.run(
            [str(ROS_PYTHON), str(SCRIPT), "run"],
            input=json.dumps([list(line) for line in lines]),
            env=self.env,
            capture_output=True,
            text=True,
            check=True,
        )
        return [(out, code) for out, code in json.loads(done.stdout)]


@pytest.fixture(scope="module")
def rosmsg(tmp_path_factory: pytest.TempPathFactory) -> Rosmsg:
    probe = subprocess.run(
        [str(ROS_PYTHON), "-c", "import rosmsg, std_msgs.msg"], capture_output=True, check=False
    )
    if not ROSMSG.is_file() or probe.returncode != 0:
        pytest.skip("Debian's rosmsg and message modules are not installed")
    root = tmp_path_factory.mktemp("ros_packages")
    subprocess.run([str(ROS_PYTHON), str(SCRIPT), "write", str(root)], check=True)
    return Rosmsg(root)


def ours(capsys: pytest.CaptureFixture[str], *argv: str) -> str:
    capsys.readouterr()
    assert main(list(argv)) == 0, argv
    return capsys.readouterr().out


def _oracle_types(rosmsg: Rosmsg, tool: str) -> list[str]:
    ((listed, _),) = rosmsg([[tool, "list"]])
    return listed.split()


def test_show_and_md5_of_every_standard_type(
    rosmsg: Rosmsg, capsys: pytest.CaptureFixture[str]
) -> None:
    kinds: tuple[tuple[str, Kind], ...] = (("rosmsg", "msg"), ("rossrv", "srv"))
    for tool, kind in kinds:
        names = [n for n in _oracle_types(rosmsg, tool) if n in type_names(kind)]
        assert len(names) >= (100 if kind == "msg" else 5), names
        lines = [[tool, action, name] for name in names for action in ("show", "md5")]
        answers = rosmsg(lines)
        for line, (want, _) in zip(lines, answers, strict=True):
            assert want, line  # the oracle did answer (an empty message: one blank line)
            assert ours(capsys, kind, line[1], line[2]) == want, line
        # what the comparison establishes, spelt out for one nested type
        if kind == "msg":
            shown = dict(zip((tuple(line) for line in lines), answers, strict=True))
            assert shown[("rosmsg", "show", "actionlib_msgs/GoalStatusArray")][0] == (
                "std_msgs/Header header\n  uint32 seq\n  time stamp\n  string frame_id\n"
                "actionlib_msgs/GoalStatus[] status_list\n  uint8 PENDING=0\n"
                "  uint8 ACTIVE=1\n  uint8 PREEMPTED=2\n  uint8 SUCCEEDED=3\n  uint8 ABORTED=4\n"
                "  uint8 REJECTED=5\n  uint8 PREEMPTING=6\n  uint8 RECALLING=7\n"
                "  uint8 RECALLED=8\n  uint8 LOST=9\n  actionlib_msgs/GoalID goal_id\n"
                "    time stamp\n    string id\n  uint8 status\n  string text\n\n"
            )


PRIMITIVES = frozenset(
    [
        "bool",
        "byte",
        "char",
        "int8",
        "uint8",
        "int16",
        "uint16",
        "int32",
        "uint32",
        "int64",
        "uint64",
        "float32",
        "float64",
        "string",
        "time",
        "duration",
    ]
)


def _declarations(text: str, package: str) -> list[str]:
    """A definition's lines without comments, blank lines or extra spaces, and every type
    named in full (``Header``: ``std_msgs/Header``; ``Point`` in geometry_msgs:
    ``geometry_msgs/Point``), as the type store keeps them."""
    out = []
    for line in text.splitlines():
        words = re.sub(r"\s*=\s*", "=", line.split("#", 1)[0]).split()
        if not words or words == ["---"]:
            out += words
            continue
        base = re.sub(r"\[\d*\]$", "", words[0])
        if "/" not in base and base not in PRIMITIVES:
            prefix = "std_msgs/" if base == "Header" else f"{package}/"
            words[0] = prefix + words[0]
        out.append(" ".join(words))
    return out


@pytest.mark.parametrize(
    ("kind", "name"),
    [
        ("msg", "std_msgs/Header"),
        ("msg", "sensor_msgs/NavSatStatus"),
        ("msg", "sensor_msgs/Imu"),
        ("msg", "geometry_msgs/PoseWithCovarianceStamped"),
        ("msg", "std_msgs/Empty"),
        ("srv", "std_srvs/SetBool"),
        ("srv", "std_srvs/Empty"),
    ],
)
def test_raw_definitions_but_for_comments(
    rosmsg: Rosmsg, capsys: pytest.CaptureFixture[str], kind: str, name: str
) -> None:
    ((want, _),) = rosmsg([[f"ros{kind}", "show", "-r", name]])
    got = ours(capsys, kind, "show", "-r", name)
    halves = "\n".join(_declarations(want, name.partition("/")[0])).split("---")
    # the store keeps a type's constants before its fields (a .msg file may mix them)
    declared = "---".join(
        "\n".join(sorted(half.split("\n"), key=lambda line: "=" not in line)) for half in halves
    ).split("\n")
    declared = [line for line in declared if line]
    assert got == "".join(line + "\n" for line in declared) + "\n"


def test_package_listings_and_names_without_a_package(
    rosmsg: Rosmsg, capsys: pytest.CaptureFixture[str]
) -> None:
    lines = [
        ["rosmsg", "package", "std_msgs"],
        ["rosmsg", "package", "geometry_msgs"],
        ["rosmsg", "package", "sensor_msgs"],
        ["rosmsg", "package", "actionlib_msgs"],
        ["rossrv", "package", "std_srvs"],
        ["rosmsg", "show", "Header"],
        ["rosmsg", "show", "Empty"],
        ["rosmsg", "md5", "Twist"],
        ["rossrv", "show", "Trigger"],
        ["rossrv", "md5", "SetBool"],
    ]
    for line, (want, _) in zip(lines, rosmsg(lines), strict=True):
        assert ours(capsys, line[0].removeprefix("ros"), *line[1:]) == want, line
    # every type Debian lists is one belvedere lists too, but tf2_ros's action and its error
    missing: set[str] = set()
    for tool, kind in (("rosmsg", "msg"), ("rossrv", "srv")):
        theirs = {n for n in _oracle_types(rosmsg, tool) if not n.startswith("actionlib/")}
        missing |= theirs - set(ours(capsys, kind, "list").split())
    assert {re.sub(r"LookupTransform.*", "LookupTransform…", n) for n in missing} <= {
        "tf2_msgs/LookupTransform…",
        "tf2_msgs/TF2Error",
    }
