"""Fuzzing message YAML as ``topic pub``, ``--pub`` and launch take it: mutated example
messages give a message that serializes and prints, or belvedere's own error."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from belvedere.errors import BelvedereError
from belvedere.msgs import message_from_args, message_to_yaml, types
from tests.fuzz._mutate import Mutation, fuzz_settings, mutations, run_bounded, text_mutant

SEEDS = (
    ("geometry_msgs/Twist", "{linear: {x: 0.2}, angular: {z: 0.5}}"),
    ("geometry_msgs/Twist", "{linear: {x: 0.2, y: 0, z: 0}, angular: {x: 0, y: 0, z: 0.5}}"),
    ("geometry_msgs/Twist", "[0.2, 0, 0]"),
    ("std_msgs/String", "data: hi"),
    ("std_msgs/Float32", "1.5"),
    ("std_msgs/Duration", "{data: {secs: 1, nsecs: 5}}"),
    ("std_msgs/Header", "{seq: 1, stamp: now, frame_id: base_link}"),
    ("sensor_msgs/JointState", "{header: auto, name: [a, b], position: [1.0, -2.0]}"),
    ("sensor_msgs/LaserScan", "{ranges: [1.0, .inf, .nan], angle_increment: 0.01}"),
    (
        "trajectory_msgs/JointTrajectory",
        "{joint_names: [j1], points: [{positions: [0.5], time_from_start: {secs: 1}}]}",
    ),
    ("std_msgs/UInt8MultiArray", "{data: [1, 2, 255]}"),
    ("geometry_msgs/PoseStamped", "{header: {frame_id: map}, pose: {orientation: {w: 1}}}"),
)
TOKENS = (
    "&a ",
    "*a",
    "&a [*a]",
    "!!python/object/apply:os.system ['true']",
    "!!binary AAAA",
    "!degrees ",
    "[",
    "]",
    "{",
    "}",
    ": ",
    ", ",
    "- ",
    "\n",
    "\t",
    "'",
    '"',
    "~",
    "null",
    "now",
    "auto",
    "1e309",
    "1.0e+309",
    "-1.0e+300",
    ".inf",
    ".nan",
    "9" * 400,
    "-" + "9" * 30,
    "0x1f",
    "0o17",
    "0b101",
    "1_000",
    "2001-12-14",
    "[" * 200,
    "é😀\u202e",
    "x" * 1000,
)


@fuzz_settings(600)
@given(st.sampled_from(SEEDS), mutations(max_edits=4))
def test_message_yaml_mutants(seed: tuple[str, str], edits: list[Mutation]) -> None:
    type_name, text = seed
    text = text_mutant(text, edits, TOKENS)
    with run_bounded(30):
        try:
            msg = message_from_args(type_name, [text], clock=lambda: (12, 34))
        except BelvedereError:
            return
        name = types().resolve(type_name)
        types().deserialize(types().serialize(msg), name)
        message_to_yaml(msg)
