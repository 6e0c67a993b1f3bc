"""The first messages of a script's subscription come as promptly as the transport allows:
the code that reads (and writes) a message type is made when the script subscribes (or
advertises), as importing genpy's classes does under ROS, not when the first message comes,
where it delayed that message (and bunched it with the next) by milliseconds of rosbags' code
generation — tens of them on a busy machine."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

from tests.waiting import DEADLINE

EARLY = """\
import rospy
from belvedere.msgs import types
from geometry_msgs.msg import Twist
from std_msgs.msg import String
from tf2_msgs.msg import TFMessage

rospy.init_node("early")
made = types().store.cache
rospy.Subscriber("/nobody_publishes", TFMessage, lambda msg: None)
print("subscriber ready:", "tf2_msgs/msg/TFMessage" in made)
rospy.Publisher("/nobody_listens", Twist, queue_size=1)
print("publisher ready:", "geometry_msgs/msg/Twist" in made)
latched = rospy.wait_for_message("/map_name", String, timeout=30)
print("latched:", latched.data)
"""


def test_a_scripts_subscription_is_ready_to_read_its_first_message(
    tmp_path: Path, peer: Any
) -> None:
    script = tmp_path / "early.py"
    script.write_text(EARLY)
    done = subprocess.run(
        [sys.executable, "-m", "belvedere", "run", str(script)],
        capture_output=True,
        text=True,
        timeout=DEADLINE,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == [
        "subscriber ready: True",
        "publisher ready: True",
        "latched: office",  # the peer's latched message, from another process
    ]
