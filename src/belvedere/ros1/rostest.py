"""``rostest`` for the scripts belvedere runs: ``rostest.rosrun(PKG, NAME, TestCase)`` runs a
test node's unittest cases into the results file ``belvedere test`` asked for
(``--gtest_output=xml:FILE``), prints rosunit's summary, shuts the node down and exits 1 if a
test failed — as ROS 1's rostest module does."""

from __future__ import annotations

import sys

from belvedere.ros1.rosunit import XML_OUTPUT_FLAG, print_unittest_summary, run_suite, unitrun

__all__ = ["XML_OUTPUT_FLAG", "rosrun", "run", "unitrun"]


def rosrun(package: str, test_name: str, test: object, sysargs: list[str] | None = None) -> None:
    """Run a rostest node's tests (a TestCase class, instance, suite or dotted name)."""
    result = run_suite(package, test_name, test, sysargs)
    print_unittest_summary(result)
    from belvedere.ros1 import rospy  # the node the tests used ends with them

    rospy.signal_shutdown("test complete")
    if not result.wasSuccessful():
        sys.exit(1)


run = rosrun
"""rostest's older name for :func:`rosrun`."""
