"""``--echo`` has stdout to itself: a stream of YAML documents a program (or a reader) can
parse, while nodes' log lines and scripts' ``output="screen"`` output go to stderr."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import yaml

from tests.conftest import EXAMPLES
from tests.waiting import DEADLINE

CHATTY = """\
import rospy
from std_msgs.msg import String

rospy.init_node("chatty")
print("a line the script printed", flush=True)
rospy.loginfo("an INFO the script logged")
rospy.logwarn("a WARN the script logged")
said = rospy.Publisher("/said", String, queue_size=1, latch=True)
said.publish(String(data="hello"))
rospy.loginfo("published")
"""

LOG_LINE = re.compile(r"^\[(DEBUG|INFO|WARN|ERROR|FATAL)\] \[")


def test_launch_echo_is_a_clean_yaml_stream(tmp_path: Path, endpoint: str) -> None:
    pkg = tmp_path / "chat"
    (pkg / "scripts").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>chat</name></package>")
    (pkg / "scripts" / "chatty.py").write_text(CHATTY)
    launch = pkg / "chat.launch"
    the_map = EXAMPLES / "rbx1_nav" / "maps" / "blank_map.yaml"
    # map_server logs INFO lines as it loads; the script prints and logs (output="screen")
    launch.write_text(
        f"""<launch>
          <node pkg="map_server" type="map_server" name="map_server" args="{the_map}"/>
          <node pkg="chat" type="chatty.py" name="chatty" output="screen" required="true"/>
        </launch>"""
    )
    done = subprocess.run(
        [sys.executable, "-m", "belvedere", "launch", str(launch), "--headless",
         "--duration", str(DEADLINE), "--echo", "/map_metadata", "--echo", "/rosout"],
        capture_output=True, text=True, timeout=2 * DEADLINE, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert not [line for line in done.stdout.splitlines() if LOG_LINE.match(line)]
    assert "a line the script printed" not in done.stdout
    documents = [d for d in yaml.safe_load_all(done.stdout) if d is not None]
    assert documents
    assert all(isinstance(d, dict) for d in documents)
    assert any("resolution" in d for d in documents)  # /map_metadata
    # what the nodes said is on stderr, as on a terminal: nothing is lost
    assert 'Loading map from image "' in done.stderr
    assert "a line the script printed" in done.stderr
    assert "an INFO the script logged" in done.stderr
