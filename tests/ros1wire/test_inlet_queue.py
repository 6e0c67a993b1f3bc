"""Messages from a ROS 1 publisher while the graph's executor is busy: the bridge keeps the
newest :data:`IN_QUEUE` of them (as a subscriber's queue keeps its newest), not every one,
and they reach the graph subscriber in order once the executor is free (Debian's rospy
publishing)."""

from __future__ import annotations

import textwrap
import threading
from pathlib import Path
from typing import Any

import pytest

from belvedere.graph import Graph
from belvedere.ros1wire import MasterHandle
from belvedere.ros1wire._bridge import IN_QUEUE
from tests.debian_ros import ROS_PYTHON
from tests.ros1wire.conftest import Ros1
from tests.waiting import DEADLINE, wait_until

pytestmark = pytest.mark.usefixtures("needs_debian_ros")

SENT = 3 * IN_QUEUE


def _flood(folder: Path) -> Path:
    """A rospy publisher that sends ``SENT`` numbered strings at once to its first
    subscriber, then says so on stdout and waits to be ended."""
    script = folder / "flood.py"
    script.write_text(
        textwrap.dedent(
            f"""
            import sys, rospy
            from std_msgs.msg import String
            rospy.init_node("flood")
            pub = rospy.Publisher("/flood", String, queue_size={SENT})
            while pub.get_num_connections() == 0 and not rospy.is_shutdown():
                rospy.sleep(0.05)
            rospy.sleep(0.3)
            for i in range({SENT}):
                pub.publish(String(data=str(i)))
            print("SENT", flush=True)
            rospy.spin()
            """
        )
    )
    return script


def test_a_busy_executor_gets_the_newest_messages_in_order(
    ros_graph: tuple[Graph, MasterHandle], tmp_path: Path
) -> None:
    graph, handle = ros_graph
    heard: list[int] = []
    busy, free = threading.Event(), threading.Event()

    def take(msg: Any) -> None:
        if not heard and not free.is_set():
            busy.set()
            free.wait(DEADLINE)  # the executor is held here while the flood is read
        heard.append(int(msg.data))

    node = graph.create_node("listener")
    graph.executor.post(lambda: node.subscribe("/flood", "std_msgs/String", take, queue_size=0))
    flood = Ros1(handle.uri).start(str(ROS_PYTHON), str(_flood(tmp_path)))
    try:
        assert flood.stdout is not None
        assert flood.stdout.readline().strip() == "SENT"
        wait_until(busy.is_set, what="the first message to hold the executor")
        # everything sent is read by the bridge while the executor is held
        wait_until(
            lambda: _newest_waiting(handle) == SENT - 1,
            what="the last message sent waiting in the bridge",
        )
        free.set()
        wait_until(
            lambda: heard and heard[-1] == SENT - 1,
            what="the last message",
            detail=lambda: heard[-5:],
        )
    finally:
        free.set()
        flood.kill()
        flood.wait()
    # what one executor job published before the hold, then the newest the bridge kept
    # while it was held: in order, ending with the last sent, far fewer than were sent
    assert heard == sorted(set(heard))
    assert heard[-1] == SENT - 1
    assert len(heard) <= 2 * IN_QUEUE < SENT


def _newest_waiting(handle: MasterHandle) -> int | None:
    inlet = handle.bridge._inlets.get("/flood")
    if inlet is None or not inlet.waiting:
        return None
    waiting = list(inlet.waiting)
    assert len(waiting) <= IN_QUEUE
    return int(waiting[-1].data)
