"""belvedere's tf (ROS 1's first tf API, over tf2) against Debian's ``tf.TransformerROS`` run
by ``/usr/bin/python3``: the same results, messages and exception texts."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
from hypothesis import given, settings

from belvedere.ros1 import rospy, tf
from tests.ros1.test_tf2_ros import TREE, at
from tests.ros1.tf_client import TfOracle, check_steps, oracle_fixture
from tests.ros1.tf_scenarios import run_steps, stamped, tf1_scenarios

pytestmark = pytest.mark.oracle


@pytest.fixture(scope="module")
def oracle() -> Iterator[TfOracle]:
    yield from oracle_fixture()


def ours(scenario: dict[str, Any]) -> list[Any]:
    cache = scenario.get("cache_time")
    target = tf.TransformerROS(True, None if cache is None else rospy.Duration(*cache))
    target.setUsingDedicatedThread(True)
    return run_steps(target, scenario["steps"])


def check(oracle: TfOracle, scenario: dict[str, Any]) -> None:
    check_steps(oracle, "tf1", scenario, ours)


POINT = {"msg": "geometry_msgs/Point", "fields": {"x": 1.0, "y": 2.0, "z": 3.0}}


def test_tree(oracle: TfOracle) -> None:
    steps: list[Any] = [["setTransform", spec, who] for _, spec, who in TREE]
    steps += [
        ["lookupTransform", "/map", "/laser", at(11)],
        ["lookupTransform", "map", "laser", at(0)],
        ["lookupTransform", "map", "nowhere", at(0)],
        ["lookupTransform", "map", "other", at(0)],
        ["lookupTransform", "map", "base", at(20)],
        ["waitForTransform", "map", "laser", at(0), {"duration": [0, 0]}],
        ["waitForTransform", "map", "nowhere", at(0), {"duration": [0, 0]}],
        ["waitForTransform", "map", "", at(0), {"duration": [0, 0]}],
        ["waitForTransform", "map", "base", at(20), {"duration": [0, 0]}],
        ["canTransform", "/map", "laser", at(0)],
        ["getLatestCommonTime", "/laser", "map"],
        ["getLatestCommonTime", "map", "other"],
        ["frameExists", "map"],
        ["frameExists", "laser"],
        ["getFrameStrings"],
        ["allFramesAsString"],
        ["allFramesAsDot"],
        ["allFramesAsDot", at(14)],
        ["lookupTransformFull", "laser", at(10.5), "laser", at(11.5), "/map"],
        ["canTransformFull", "laser", at(10.5), "laser", at(11.5), "map"],
        ["transformPoint", "map", stamped("PointStamped", "laser", [11, 0], point=POINT)],
        ["transformPoint", "/map", stamped("PointStamped", "/laser", [0, 0], point=POINT)],
        ["asMatrix", "map", {"msg": "std_msgs/Header", "fields": {"frame_id": "camera"}}],
        ["fromTranslationRotation", [1.0, 2.0, 3.0], [0.0, 0.0, 0.6, 0.8]],
        ["lookupTwist", "base", "map", at(11), {"duration": [0, 500_000_000]}],
        ["lookupTwist", "laser", "odom", at(0), {"duration": [0, 200_000_000]}],
        ["getTFPrefix"],
    ]
    check(oracle, {"cache_time": None, "steps": steps})


@settings(max_examples=300)
@given(tf1_scenarios())
def test_generated_scenarios(oracle: TfOracle, scenario: dict[str, Any]) -> None:
    check(oracle, scenario)


def test_waiting_needs_a_listener() -> None:
    transformer = tf.Transformer()
    with pytest.raises(tf.Exception, match="cannot wait for transform without a dedicated"):
        transformer.waitForTransform("a", "b", rospy.Time(0), rospy.Duration(1))


def test_exceptions_are_tf2s() -> None:
    from belvedere.ros1 import tf2_ros

    assert tf.Exception is tf2_ros.TransformException
    assert tf.LookupException is tf2_ros.LookupException
    assert tf.transformations.quaternion_from_euler(0, 0, 0).tolist() == [0.0, 0.0, 0.0, 1.0]
