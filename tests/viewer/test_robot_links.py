"""A RobotModel display draws a link only where TF places it: a link with no transform (a
wheel whose joint nobody publishes) is not drawn at the fixed frame's origin, and the
display says which link has none, as rviz does."""

from __future__ import annotations

import socket

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph
from belvedere.viewer import Viewer
from belvedere.viewer._frame_displays import RobotModelDisplay
from belvedere.viewer._status import Level
from tests.waiting import wait_until

URDF = """<robot name="cart">
  <link name="base_link"><visual><geometry><box size="0.4 0.3 0.1"/></geometry></visual></link>
  <link name="wheel"><visual><geometry><cylinder radius="0.05" length="0.02"/></geometry>
  </visual></link>
  <joint name="wheel_joint" type="continuous">
    <parent link="base_link"/><child link="wheel"/><origin xyz="0 0.2 0"/>
  </joint>
</robot>"""


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


def test_a_link_without_a_transform_is_not_drawn_at_the_origin() -> None:
    graph = Graph(sim_time=True)
    model = RobotModel.from_string(URDF, path="cart.urdf")
    viewer = Viewer(graph, model=model, port=_free_port(), fixed_frame="odom")
    try:
        display = viewer.add_display("RobotModel")
        node = graph.create_node("odometry")
        tf = node.publisher("/tf", "tf2_msgs/TFMessage")

        def place(child: str, parent: str, x: float) -> None:
            now = node.now_ns()
            tf.publish_data({"transforms": [{
                "header": {"frame_id": parent, "stamp": [now // 10**9, now % 10**9]},
                "child_frame_id": child,
                "transform": {"translation": {"x": x}, "rotation": {"w": 1.0}},
            }]})  # fmt: skip

        ticker = node.timer(0.1, lambda: place("base_link", "odom", 1.0))
        graph.run(duration=1.0)
        assert isinstance(display, RobotModelDisplay)

        def drawn(link: str) -> bool:
            drawing = display.drawing
            return drawing is not None and bool(drawing.links[link].frame.visible)

        missing = (Level.ERROR, "No transform from [wheel] to [odom]")
        wait_until(
            lambda: drawn("base_link") and display.status.get("Transform") == missing,
            what="the placed base drawn, and the wheel said to have no transform",
            detail=lambda: display.status.get("Transform"),
        )
        assert display.drawing is not None
        assert tuple(display.drawing.links["base_link"].frame.position) == (1.0, 0.0, 0.0)
        assert not drawn("wheel")  # no joint state: no transform, nowhere to draw it
        ticker.cancel()

        def place_both() -> None:
            place("base_link", "odom", 1.0)
            place("wheel", "base_link", 0.0)

        node.timer(0.1, place_both)
        graph.run(duration=1.0)
        wait_until(
            lambda: (
                drawn("wheel") and display.status.get("Transform") == (Level.OK, "Transform OK")
            ),
            what="the wheel drawn once placed",
        )
    finally:
        viewer.close()
        graph.shutdown()
