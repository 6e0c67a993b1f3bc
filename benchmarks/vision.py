"""A camera's pictures through cv_bridge and OpenCV and out again, as a course vision node
does: a simulated 640x480 camera at 30 Hz, each frame taken in with ``imgmsg_to_cv2``
(bgr8), made grey, blurred, its edges found (Canny), marked, and published again with
``cv2_to_imgmsg``.

Prints the CPU time per frame (the whole process: physics, rendering, the node) and the
node's own share, each as a ratio against the frame budget of one core at 30 Hz (1/30 s,
the reference): below 1 keeps up on one core.

    python benchmarks/vision.py [--seconds 5]
"""

from __future__ import annotations

import argparse
import math
import time
from typing import Any

import cv2

from belvedere.description.urdf import Pose, RobotModel
from belvedere.graph import Graph
from belvedere.ros1._classes import to_store
from belvedere.ros1.cv_bridge import CvBridge
from belvedere.sim.physics import PhysicsSimulation
from belvedere.world import read_world_string

RATE = 30.0
CAMERA_ROBOT = """<robot name="eye">
  <link name="base"><inertial><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <gazebo reference="base">
    <sensor type="camera" name="eye_camera">
      <update_rate>30</update_rate>
      <camera><horizontal_fov>1.0</horizontal_fov>
        <image><width>640</width><height>480</height><format>R8G8B8</format></image>
        <clip><near>0.02</near><far>100</far></clip></camera>
      <plugin name="eye_plugin" filename="libgazebo_ros_camera.so">
        <cameraName>eye</cameraName><frameName>base</frameName></plugin>
    </sensor>
  </gazebo>
</robot>"""
WORLD = """<sdf version="1.6"><world name="default">
  <include><uri>model://ground_plane</uri></include>
  <include><uri>model://sun</uri></include>
  <model name="red_box"><static>true</static><pose>2 0 0.5 0 0 0</pose>
    <link name="link"><visual name="visual"><geometry><box><size>1 1 1</size></box></geometry>
    </visual></link></model>
</world></sdf>"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=5.0, help="simulated seconds")
    args = parser.parse_args()

    graph = Graph()
    sim = PhysicsSimulation(graph, read_world_string(WORLD, "world.sdf"))
    robot = RobotModel.from_string(CAMERA_ROBOT, path="eye.urdf")
    sim.spawn(robot, pose=Pose((4.0, 0.0, 0.5), (0.0, 0.0, math.pi)))
    sim.engine.m.body_gravcomp[:] = 1.0
    bridge = CvBridge()
    node = graph.create_node("edges")
    out = node.publisher("/edges", "sensor_msgs/Image")
    spent = [0.0]
    frames = [0]

    def on_image(msg: Any) -> None:
        start = time.thread_time()
        picture = bridge.imgmsg_to_cv2(msg, "bgr8")
        grey = cv2.GaussianBlur(cv2.cvtColor(picture, cv2.COLOR_BGR2GRAY), (5, 5), 0)
        edges = cv2.Canny(grey, 50, 150)
        cv2.circle(edges, (60, 60), 30, 255, -1)
        out.publish(to_store(bridge.cv2_to_imgmsg(edges, "mono8")))  # as rospy sends it
        spent[0] += time.thread_time() - start
        frames[0] += 1

    node.subscribe("/eye/image_raw", "sensor_msgs/Image", on_image)
    graph.run(duration=0.2)  # the first frame's set-up (renderer, first imports) not counted
    spent[0], frames[0] = 0.0, 0
    cpu = time.process_time()
    graph.run(duration=args.seconds)
    cpu = time.process_time() - cpu
    if not frames[0]:
        msg = "no frames (is EGL rendering available?)"
        raise SystemExit(msg)
    budget = 1.0 / RATE
    print(f"frames: {frames[0]} of 640x480 in {args.seconds:g} simulated s")
    print(f"reference: frame budget at {RATE:g} Hz on one core {budget * 1e3:.1f} ms")
    total = cpu / frames[0]
    node_share = spent[0] / frames[0]
    print(
        f"whole process (physics + rendering + node): {total * 1e3:.2f} ms CPU per frame, "
        f"ratio {total / budget:.3f} of the budget"
    )
    print(
        f"the node (cv_bridge in, OpenCV, cv_bridge out): {node_share * 1e3:.2f} ms CPU "
        f"per frame, ratio {node_share / budget:.3f} of the budget"
    )


if __name__ == "__main__":
    main()
