"""Differential tests of belvedere's rospy against Debian's ROS 1: the learner scripts of
``scripts/`` print the same lines (times, anonymous suffixes and pids masked) under a real
roscore and under ``belvedere run`` (see :mod:`tests.ros1.rospy_oracle`)."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from tests.ros1.rospy_oracle import (
    CASES,
    SCRIPTS,
    Case,
    Master,
    Output,
    differences,
    lines,
    mask,
    master,
    missing_oracle,
    run_belvedere,
    run_ros,
)

pytestmark = pytest.mark.oracle

# What belvedere still does differently (strict: a fix shows as XPASS, so the mark goes).
EXIT_LINE = (
    "'belvedere run' ends with 'required node /NAME exited: shutting down' on the first "
    "script's stderr (rosrun prints nothing)"
)
PUB_NAME = "Publisher/Subscriber .name is the name as given ('chatter'), rospy's is resolved"
KNOWN: dict[str, str] = {
    "chatter": f"{PUB_NAME}; {EXIT_LINE}",
    "latched": EXIT_LINE,
    "cmd_vel": EXIT_LINE,
    "wait_for_message": "'rospy.exceptions' is not an attribute of rospy after 'import rospy'; "
    f"wait_for_message(timeout=rospy.Duration(...)) raises TypeError; {EXIT_LINE}",
    "services": "wait_for_service(timeout=rospy.Duration(...)) raises TypeError; "
    "ServiceException is a ROSException (rospy's is not); a request that does not serialize "
    f"raises ROSSerializationException (rospy: genpy's SerializationError); {EXIT_LINE}",
    "params": EXIT_LINE,
    "names": "resolve_name('~') has no trailing '/'; search_param('~x') raises ValueError "
    f"(rospy: ROSException 'cannot search for parameter: ...'); {PUB_NAME}; {EXIT_LINE}",
    "anonymous": EXIT_LINE,
    "time": EXIT_LINE,
    "shutdown": f"'rospy.core' is not an attribute of rospy after 'import rospy'; {EXIT_LINE}",
    "logging": "Log.topics lacks the node's /clock subscription; a new subscriber of the "
    f"latched /rosout gets its last message twice; {EXIT_LINE}",
    "debug_level": EXIT_LINE,
    "header_seq": "publish() leaves header.seq of the caller's message as it was (rospy sets "
    f"it); {EXIT_LINE}",
}
KNOWN["names_remapped"] = KNOWN["names"]


def _cases() -> list[object]:
    return [
        pytest.param(
            case,
            id=case.name,
            marks=[pytest.mark.xfail(reason=KNOWN[case.name], strict=True)]
            if case.name in KNOWN
            else [],
        )
        for case in CASES
    ]


@pytest.fixture(scope="module")
def roscore() -> Iterator[Master]:
    reason = missing_oracle()
    if reason is not None:
        pytest.skip(reason)
    with master() as core:
        yield core


def _shown(case: Case, outputs: dict[str, Output]) -> str:
    return "\n".join(
        f"{name} (exit {out.returncode}):\n  stdout: {lines(case, out.stdout)}\n"
        f"  stderr: {lines(case, out.stderr)}"
        for name, out in outputs.items()
    )


@pytest.mark.parametrize("case", _cases())
def test_same_lines_as_ros(roscore: Master, case: Case) -> None:
    expected = run_ros(case, roscore)
    # the scripts end by themselves under ROS: anything else is a broken case, not a finding
    assert all(out.returncode == 0 for out in expected.values()), _shown(case, expected)
    got = run_belvedere(case)
    compared, found = differences(case, expected, got)
    assert compared > 0
    assert not found, (
        f"{case.name}: {len(found)} stream(s) differ from ROS's ({compared} lines compared)\n"
        + "\n".join(found)
    )


def test_mask_hides_only_what_varies_under_ros() -> None:
    text = (
        "[INFO] [1795480442.905545]: hello 1.5\n"
        "[WARN] [1795480442.905545, 12.500000]: at sim time\n"
        "name: /listener_4242_1795480442905 pid[4242]\n"
        "[INFO] [TIME]: seq 12 at 3.25\n"
        "['Traceback (most recent call last):\\n', '  File \"/usr/lib/rospy/x.py\", line 6, in f\\n"
        "    g()\\n', '  File \"%s\", line 3, in h\\n    raise E\\n', 'E\\n']\n"
        % (SCRIPTS / "s.py")
    )
    assert mask(text).splitlines() == [
        "[INFO] [TIME]: hello 1.5",
        "[WARN] [TIME, TIME]: at sim time",
        "name: /listener_ANON pid[PID]",
        "[INFO] [TIME]: seq 12 at 3.25",
        "['Traceback (most recent call last):\\n', '  File \"%s\", line 3, in h\\n    raise E\\n', "
        "'E\\n']" % (SCRIPTS / "s.py"),
    ]


def test_differences_are_per_stream_and_show_a_diff() -> None:
    case = Case("pair", CASES[0].scripts)
    ros = {
        "talker": Output("a\nb\n", "", 0),
        "listener": Output("x\n", "[WARN] [1.0]: w\n", 0),
    }
    same = {
        "talker": Output("a\nb\n", "", 0),
        "listener": Output("x\n", "[WARN] [2.0]: w\n", 0),
    }
    assert differences(case, ros, same) == (4, [])
    other = {"talker": Output("a\nc\n", "", 0), "listener": Output("x\n", "", 1)}
    compared, found = differences(case, ros, other)
    assert compared == 4
    assert len(found) == 3
    assert "-b\n+c" in found[0]
    assert "ROS listener stderr" in found[1]
    assert found[2] == "listener: exit status 1, ROS's is 0"
