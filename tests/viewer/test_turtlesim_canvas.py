"""turtlesim's window in the viewer: the canvas lies on the floor with the world's
coordinates, is sent again when it changes, and the teleop panel drives turtle1."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from belvedere.graph import Graph
from belvedere.nodes.turtlesim import TurtlesimNode
from belvedere.sim.turtlesim import BACKGROUND, PEN, SIZE
from belvedere.viewer import Viewer
from tests.conftest import free_port


def test_the_canvas_is_drawn_where_the_turtles_are_and_follows_them() -> None:
    graph = Graph()
    sim = TurtlesimNode(graph.create_node("turtlesim"))
    viewer = Viewer(graph, port=free_port(), canvases=[sim])
    try:
        (drawing,) = viewer.canvases
        drawing.period = 0.0  # every frame, for the test
        drawing.next_at = 0.0  # (the viewer's own thread may have drawn it once already)
        viewer.render_once()
        handle = drawing.handle
        assert handle is not None
        assert tuple(handle.position) == pytest.approx((SIZE / 2, SIZE / 2, -0.003))
        first = drawing.shown
        assert first is not None
        assert first.shape == (500, 500, 3)
        assert tuple(first[5, 5]) == BACKGROUND
        assert viewer.cmd_pub.name == "/turtle1/cmd_vel"
        assert viewer.fixed_frame == "world"  # the tf demo's frame, which the canvas lies in
        viewer.render_once()
        assert drawing.handle is handle  # nothing changed: nothing sent

        cmd = graph.create_node("probe").publisher("/turtle1/cmd_vel", "geometry_msgs/Twist")
        cmd.publish_data({"linear": {"x": 1.0}})
        graph.run(duration=1.5)
        viewer.render_once()
        assert drawing.handle is not handle
        shown: Any = drawing.shown
        centre = round(SIZE / 2 * 45)
        assert tuple(shown[centre, centre + 20]) == PEN  # the trail behind the turtle
        # row 0 of the picture is the top of turtlesim's window; viser's image starts at the
        # bottom, so the drawing sends it upside down
        assert np.array_equal(np.asarray(drawing.handle.image), shown[::-1])
    finally:
        viewer.close()
        graph.shutdown()
