"""Differential tests: belvedere's robot_state_publisher against Debian's (ROS 1, 1.15).

The same model, parameters and ``joint_states`` sequence go to both; what they publish on
``/tf`` and ``/tf_static`` (frames, order, stamps, seq, translations, rotations) must agree.
"""

from __future__ import annotations

import random
from collections.abc import Iterator
from pathlib import Path

import pytest

from belvedere.description.urdf import RobotModel
from belvedere.graph import NS
from tests.conftest import EXAMPLES
from tests.tf.ros1 import (
    Case,
    JointStates,
    Roscore,
    compare,
    missing_oracle,
    run_belvedere,
    run_oracle,
    start_roscore,
)

LIMIT = '<limit lower="-3" upper="3" effort="1" velocity="1"/>'


def _joint(name: str, kind: str, parent: str, child: str, extra: str = "") -> str:
    limit = LIMIT if kind in ("revolute", "prismatic") else ""
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f"{extra}{limit}</joint>"
    )


def _robot(links: list[str], joints: list[str]) -> str:
    return (
        '<robot name="generated">'
        + "".join(f'<link name="{n}"/>' for n in links)
        + "".join(joints)
        + "</robot>"
    )


MIMIC = _robot(
    ["base", "l1", "l2", "l3", "l4", "l5"],
    [
        _joint(
            "lead",
            "revolute",
            "base",
            "l1",
            '<origin xyz="0.1 0 0.2" rpy="0 0 0.5"/><axis xyz="0 0 1"/>',
        ),
        _joint(
            "follow",
            "revolute",
            "l1",
            "l2",
            '<origin xyz="0.3 0 0"/><axis xyz="0 1 0"/>'
            '<mimic joint="lead" multiplier="-2" offset="0.25"/>',
        ),
        # a mimic of a mimic: its leader's value exists only when the name order allows
        _joint("chain", "prismatic", "l2", "l3", '<axis xyz="1 0 0"/><mimic joint="follow"/>'),
        _joint(
            "a_before",
            "continuous",
            "l3",
            "l4",
            '<axis xyz="0 0 1"/><mimic joint="lead" multiplier="0.5"/>',
        ),
        _joint("finger", "prismatic", "l1", "l5", '<axis xyz="0 1 0"/><mimic joint="lead"/>'),
    ],
)
AXES = _robot(
    ["base", "l1", "l2", "l3", "l4"],
    [
        _joint(
            "slide",
            "prismatic",
            "base",
            "l1",
            '<origin xyz="0 0 0.1" rpy="0.2 -0.4 1.1"/><axis xyz="0 0 2"/>',
        ),
        _joint("slant", "prismatic", "l1", "l2", '<axis xyz="1 1 0"/>'),
        _joint(
            "turn",
            "revolute",
            "l2",
            "l3",
            '<origin xyz="0.5 0 0" rpy="1.5707963 0 0"/><axis xyz="0 3 4"/>',
        ),
        _joint("spin", "continuous", "l3", "l4", '<axis xyz="0.1 -0.2 0.3"/>'),
    ],
)
CHAINS = _robot(
    ["base", "f1", "f2", "f3", "w1", "w2", "p1", "fl", "c1"],
    [
        _joint("fixed_a", "fixed", "base", "f1", '<origin xyz="0.1 0.2 0.3" rpy="0.3 0.2 0.1"/>'),
        _joint("fixed_b", "fixed", "f1", "f2", '<origin xyz="-1 0 0.5" rpy="3.14159 0 -1.2"/>'),
        _joint(
            "Fixed_c", "fixed", "f2", "f3", '<origin xyz="0 0 0" rpy="0 1.5707963267948966 0"/>'
        ),
        _joint(
            "wheel_left",
            "continuous",
            "base",
            "w1",
            '<origin xyz="0 0.2 0" rpy="-1.5707963 0 0"/><axis xyz="0 0 1"/>',
        ),
        _joint(
            "wheel_right",
            "continuous",
            "base",
            "w2",
            '<origin xyz="0 -0.2 0" rpy="1.5707963 0 0"/><axis xyz="0 0 -1"/>',
        ),
        _joint("plane", "planar", "base", "p1", '<origin xyz="1 1 0"/><axis xyz="0 0 1"/>'),
        _joint("free", "floating", "base", "fl", '<origin xyz="2 0 0"/>'),
        _joint(
            "caster",
            "continuous",
            "f3",
            "c1",
            '<origin xyz="0.05 0 -0.02" rpy="0 0 2.5"/><axis xyz="0 0 1"/>',
        ),
    ],
)


def _sequence(model: RobotModel, seed: int) -> list[JointStates]:
    """Messages that exercise the rules: all joints, a throttled one, a later one, a subset
    with an unknown name, a mimic follower named outright, a refused one (fewer positions
    than names), one stamped in the past, a repeated name."""
    rng = random.Random(seed)
    free = [
        j.name
        for j in model.joints
        if j.type in ("revolute", "continuous", "prismatic") and j.mimic is None
    ]
    named = [j.name for j in model.joints if j.mimic is not None]

    def values(names: list[str]) -> list[float]:
        return [rng.uniform(-3, 3) for _ in names]

    t = 40 * NS
    out = [
        JointStates(t, free, values(free)),
        JointStates(t + 10_000_000, free, values(free)),
        JointStates(t + 20_000_000, free, values(free)),
        JointStates(t + 30_000_000, [*free[:1], "not_in_the_model"], [*values(free[:1]), 1.0]),
        JointStates(t + 100_000_000, free + named, values(free + named)),
        JointStates(t + 200_000_000, free, values(free)[:-1] if free else []),
        JointStates(t - NS, free, values(free)),
        JointStates(t + 300_000_000, free + free[:1], values(free + free[:1])),
        JointStates(t + 400_000_000, list(reversed(free)), [0.0] * len(free)),
    ]
    return out


def _example(path: Path) -> str:
    return RobotModel.from_path(path).to_urdf()


def _cases() -> list[tuple[str, str, dict[str, object]]]:
    return [
        ("mbot", "mbot_description/urdf/xacro/gazebo/mbot_gazebo.xacro", {}),
        ("marm", "marm_description/urdf/marm.xacro", {"tf_prefix": "arm1"}),
        ("mimic", MIMIC, {}),
        ("axes", AXES, {"publish_frequency": 10.0}),
        ("chains", CHAINS, {"ignore_timestamp": True}),
        ("slow", MIMIC, {"publish_frequency": 0.0, "tf_prefix": "/robot2"}),
    ]


CASES = _cases()


@pytest.fixture(scope="module")
def roscore(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Roscore]:
    reason = missing_oracle()
    if reason is not None:
        pytest.skip(reason)
    yield from start_roscore(tmp_path_factory.mktemp("ros_home"))


def make_case(name: str, source: str, params: dict[str, object]) -> Case:
    urdf = source if source.startswith("<robot") else _example(EXAMPLES / source)
    model = RobotModel.from_string(urdf)
    return Case(name, urdf, _sequence(model, seed=len(name)), params)


@pytest.mark.parametrize(("name", "source", "params"), CASES, ids=[c[0] for c in CASES])
def test_matches_ros1_robot_state_publisher(
    roscore: Roscore, tmp_path: Path, name: str, source: str, params: dict[str, object]
) -> None:
    case = make_case(name, source, params)
    expected, stderr = run_oracle(roscore, case, tmp_path)
    actual = run_belvedere(case)
    result = compare(expected, actual)
    assert not result.mismatches, "\n".join(result.mismatches) + "\n" + stderr
    assert result.transforms > 0
    assert result.max_translation <= 1e-12, result
    assert result.max_rotation <= 1e-12, result
