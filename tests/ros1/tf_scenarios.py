"""Scenarios for tf2_ros's ``Buffer`` and tf's ``Transformer``: method calls in turn, with
times, durations and messages as tagged dictionaries (``{"time": [secs, nsecs]}``,
``{"duration": …}``, ``{"msg": "pkg/Type", "fields": {…}}``), run on belvedere's classes here
and on Debian's in ``tf_oracle.py``; and hypothesis strategies that make them."""

from __future__ import annotations

import math
from typing import Any

from hypothesis import strategies as st

from belvedere.ros1 import message_class, rospy
from tests.ros1.tf_client import encode
from tests.ros1.tf_steps import Steps

Step = list[Any]

FRAMES = ["a", "b", "c", "d", "e"]


run_steps = Steps(rospy, message_class, encode).run
"""A scenario's steps run on belvedere's classes, each step's result (or error) encoded."""


# --- strategies ----------------------------------------------------------------------------


def transform_stamped(
    parent: str, child: str, stamp: list[int], t: list[float], q: list[float]
) -> dict[str, Any]:
    return {
        "msg": "geometry_msgs/TransformStamped",
        "fields": {
            "header": {
                "msg": "std_msgs/Header",
                "fields": {"frame_id": parent, "stamp": {"time": stamp}},
            },
            "child_frame_id": child,
            "transform": {
                "msg": "geometry_msgs/Transform",
                "fields": {
                    "translation": _xyz("geometry_msgs/Vector3", t),
                    "rotation": {
                        "msg": "geometry_msgs/Quaternion",
                        "fields": dict(zip("xyzw", q, strict=True)),
                    },
                },
            },
        },
    }


def _xyz(kind: str, v: list[float]) -> dict[str, Any]:
    return {"msg": kind, "fields": dict(zip("xyz", v, strict=True))}


def _unit(q: list[float]) -> list[float]:
    n = math.sqrt(sum(c * c for c in q))
    return [c / n for c in q] if n > 1e-3 else [0.0, 0.0, 0.0, 1.0]


NSECS = [0, 0, 0, 250_000_000, 500_000_000, 123_456_789]
stamps = st.tuples(st.integers(0, 12), st.sampled_from(NSECS)).map(list)
query_times = st.one_of(st.just([0, 0]), stamps).map(lambda s: {"time": s})
vectors = st.lists(st.floats(-5.0, 5.0, allow_nan=False), min_size=3, max_size=3)
rotations = st.one_of(
    st.lists(st.floats(-1.0, 1.0, allow_nan=False), min_size=4, max_size=4).map(_unit),
    st.sampled_from(
        [
            [0.0, 0.0, 0.0, 1.0],
            [0.0, 0.0, 0.7071, 0.7071],  # within tf2's tolerance, not of length 1
            [0.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 1.02],
            [math.nan, 0.0, 0.0, 1.0],
        ]
    ),
)
# mostly frames of the tree; now and then one tf2 refuses or never heard of
frames = st.sampled_from([*FRAMES * 8, "", "/a", "/b", "f"])


@st.composite
def transform_steps(draw: st.DrawFn, names: st.SearchStrategy[str] = frames) -> Step:
    """A transform to store, mostly from an earlier frame of :data:`FRAMES` to a later one
    (a tree), sometimes backwards (a loop), to itself, or with a name tf2 refuses."""
    child = draw(names)
    if child in FRAMES and child != FRAMES[0] and draw(st.integers(0, 5)):
        parent = draw(st.sampled_from(FRAMES[: FRAMES.index(child)]))
    else:
        parent = draw(names)
    spec = transform_stamped(parent, child, draw(stamps), draw(vectors), draw(rotations))
    static = draw(st.integers(0, 4)) == 0
    authority = draw(st.sampled_from(["me", "you", "default_authority"]))
    return ["set_transform_static" if static else "set_transform", spec, authority]


def _tf2_query(draw: st.DrawFn) -> Step:
    target, source, fixed = draw(frames), draw(frames), draw(frames)
    when, other = draw(query_times), draw(query_times)
    zero = {"duration": [0, 0]}
    return draw(
        st.sampled_from(
            [
                ["lookup_transform", target, source, when],
                ["lookup_transform", target, source, when, zero],
                ["lookup_transform_core", target, source, when],
                ["can_transform", target, source, when, zero, True],
                ["can_transform", target, source, when],
                ["can_transform_core", target, source, when],
                ["lookup_transform_full", target, when, source, other, fixed],
                ["can_transform_full", target, when, source, other, fixed, zero, True],
                ["get_latest_common_time", target, source],
                ["all_frames_as_string"],
                ["all_frames_as_yaml"],
                ["_allFramesAsDot"],
                ["_frameExists", target],
                ["_getFrameStrings"],
            ]
        )
    )


@st.composite
def tf2_scenarios(draw: st.DrawFn) -> dict[str, Any]:
    """A fresh ``tf2_ros.Buffer``: transforms stored, then queries, more transforms and the
    odd ``clear`` interleaved."""
    steps = draw(st.lists(transform_steps(), min_size=3, max_size=14))
    for _ in range(draw(st.integers(4, 14))):
        kind = draw(st.integers(0, 12))
        if kind == 0:
            steps.append(["clear"])
        elif kind <= 2:
            steps.append(draw(transform_steps()))
        else:
            steps.append(_tf2_query(draw))
    cache = draw(st.sampled_from([None, None, [5, 0], [2, 500_000_000]]))
    return {"cache_time": cache, "steps": steps}


def stamped(kind: str, frame: str, stamp: list[int], **fields: Any) -> dict[str, Any]:
    header = {"msg": "std_msgs/Header", "fields": {"frame_id": frame, "stamp": {"time": stamp}}}
    return {"msg": f"geometry_msgs/{kind}", "fields": {"header": header, **fields}}


def _tf1_query(draw: st.DrawFn) -> Step:
    target, source, fixed = draw(tf1_frames), draw(tf1_frames), draw(tf1_frames)
    when, other = draw(query_times), draw(query_times)
    stamp = when["time"]
    p, v = draw(vectors), draw(vectors)
    q = draw(rotations.filter(lambda r: not any(math.isnan(c) for c in r)))
    point = _xyz("geometry_msgs/Point", p)
    v3 = _xyz("geometry_msgs/Vector3", v)
    quaternion = {"msg": "geometry_msgs/Quaternion", "fields": dict(zip("xyzw", q, strict=True))}
    pose = {"msg": "geometry_msgs/Pose", "fields": {"position": point, "orientation": quaternion}}
    return draw(
        st.sampled_from(
            [
                ["lookupTransform", target, source, when],
                ["canTransform", target, source, when],
                ["waitForTransform", target, source, when, {"duration": [0, 0]}],
                ["getLatestCommonTime", target, source],
                ["frameExists", target],
                ["getFrameStrings"],
                ["allFramesAsString"],
                ["allFramesAsDot"],
                ["lookupTransformFull", target, when, source, other, fixed],
                ["canTransformFull", target, when, source, other, fixed],
                ["transformPoint", target, stamped("PointStamped", source, stamp, point=point)],
                ["transformPose", target, stamped("PoseStamped", source, stamp, pose=pose)],
                ["transformVector3", target, stamped("Vector3Stamped", source, stamp, vector=v3)],
                [
                    "transformQuaternion",
                    target,
                    stamped("QuaternionStamped", source, stamp, quaternion=quaternion),
                ],
                ["asMatrix", target, {"msg": "std_msgs/Header", "fields": {"frame_id": source}}],
            ]
        )
    )


# tf strips a leading "/" where tf2 refuses it
tf1_frames = st.sampled_from([*FRAMES * 6, "/a", "/b", "/c", "", "f"])


@st.composite
def tf1_scenarios(draw: st.DrawFn) -> dict[str, Any]:
    """A fresh ``tf.TransformerROS``: transforms set, then queries."""
    steps = [
        ["setTransform", step[1], step[2]]
        for step in draw(st.lists(transform_steps(), min_size=3, max_size=14))
    ]
    for _ in range(draw(st.integers(4, 14))):
        kind = draw(st.integers(0, 12))
        if kind == 0:
            steps.append(["clear"])
        elif kind <= 2:
            step = draw(transform_steps())
            steps.append(["setTransform", step[1], step[2]])
        else:
            steps.append(_tf1_query(draw))
    return {"cache_time": draw(st.sampled_from([None, [5, 0]])), "steps": steps}
