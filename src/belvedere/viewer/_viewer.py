"""The viewer: rviz in the browser, a node on the graph, built on viser.

Rendering runs on its own thread at the Frame Rate (30 Hz) with the latest state; subscription
callbacks only queue messages, so the viewer never slows the graph (it drops frames instead).
The side panel is rviz's: Global Options, Global Status, the Displays tree, Views (each
browser tab has its own camera and view), Time, Tools, and — when something listens — teleop.
This module builds the server and that panel; the displays, their drawing and their saving as a
config are the viewer's base class's (``_display_host``).
"""

from __future__ import annotations

import contextlib
import io
import logging
import math
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, Protocol

from belvedere.description.urdf import RobotModel
from belvedere.errors import BelvedereError
from belvedere.graph import NS, Graph, GraphTopics, Node, process_node_name
from belvedere.packages import PackageIndex
from belvedere.tf import JointStatePublisher, Transform, TransformListener, quat_xyzw_from_rpy
from belvedere.viewer._access import page_url, serve_viser, viewer_access
from belvedere.viewer._canvas import Canvas, CanvasDrawing
from belvedere.viewer._catalog import DISPLAYS
from belvedere.viewer._display import Display, DisplayContext
from belvedere.viewer._display_host import _DisplayHost
from belvedere.viewer._gamepad import ViewerGamepad
from belvedere.viewer._insert import world_editing
from belvedere.viewer._panel import DisplayPanel, set_handle
from belvedere.viewer._rviz import RvizConfig
from belvedere.viewer._status import Status
from belvedere.viewer._views import (
    CAMERA_FOV,
    CAMERA_LOOK_AT,
    CAMERA_POSITION,
    VIEW_TYPES,
    ViewState,
    floor_point,
)
from belvedere.viewer._windows import ImageWindows
from belvedere.viewer._world import WorldDrawing
from belvedere.world import WorldModel

__all__ = ["SimControls", "Viewer"]

logger = logging.getLogger(__name__)


class SimControls(Protocol):
    """What a simulation offers the viewer's buttons."""

    def pause(self, paused: bool) -> None: ...
    def step(self) -> None: ...
    def reset(self) -> None: ...
    def set_rtf(self, rtf: float | None) -> None: ...


class Viewer(_DisplayHost):
    """A browser view of the graph: displays, views, tools, teleop, joint sliders."""

    def __init__(
        self,
        graph: Graph,
        *,
        model: RobotModel | None = None,
        host: str = "127.0.0.1",
        port: int = 8080,
        fixed_frame: str | None = None,
        rviz: RvizConfig | None = None,
        joint_publisher: JointStatePublisher | None = None,
        sim: SimControls | None = None,
        packages: PackageIndex | None = None,
        rate_hz: float | None = None,
        world: WorldModel | None = None,
        world_poses: Callable[[], Mapping[str, Transform]] | None = None,
        allow_origins: Sequence[str] = (),
        token: str | None = None,
        cmd_vel: str = "/cmd_vel",
        rviz_path: str | Path | None = None,
        canvases: Sequence[Canvas] = (),
    ) -> None:
        """``world``: models drawn in the fixed frame (Gazebo's world frame);
        ``world_poses``: where the movable ones are now (called each frame).
        ``allow_origins``: web origins besides the viewer's own page that may connect;
        ``token``: what a client must show (default: a new one when ``host`` is not loopback,
        none when it is; it is in :attr:`url`). ``canvases``: 2D simulations drawn on the floor
        (turtlesim's window); the teleop drives the first one's ``cmd_vel`` unless told."""
        self.graph = graph
        self.access = viewer_access(host, allow_origins=allow_origins, token=token)
        self.server = serve_viser(self.access, host, port)
        self.scene, self.gui = self.server.scene, self.server.gui
        # rviz lights the scene with plain lights and draws no shadows; viser's image-based
        # lighting and shadow pass cost a software renderer (no GPU) half its frame rate.
        self.scene.configure_environment_map(None)
        self.scene.configure_default_lights(True, cast_shadow=False)
        # In their place, light every side a little, as rviz's ambient light does.
        self.scene.add_light_ambient("/ambient_light", intensity=1.2)
        self.node: Node = graph.create_node(process_node_name("belvedere_viewer"))
        self.tf = TransformListener(self.node)
        self.topics = GraphTopics(graph)
        self.model = model
        self.rviz = rviz
        self.rviz_path = rviz_path
        self.fixed_frame = (
            fixed_frame
            or (rviz.fixed_frame if rviz else None)
            or (model.root_link.name if model else None)
            # the canvas lies in the scene's own frame: the course's tf demo calls it world
            or ("world" if canvases else "map")
        )
        self.ctx = DisplayContext(
            node=self.node,
            scene=self.scene,
            gui=self.gui,
            buffer=self.tf.buffer,
            topic_type=self.topics.type_of,
            model=model,
            packages=packages,
        )
        self.windows = ImageWindows(self.node, self.gui, self.topics, self.ctx.docked)
        self.world = WorldDrawing(self.scene, world) if world else None
        self.world_poses = world_poses
        self.displays: list[Display] = []
        self.panels: dict[int, DisplayPanel] = {}
        self.global_status = Status()
        self.rate_hz = rate_hz or float(rviz.frame_rate if rviz else 30.0)
        self.frames_rendered = 0
        self.last_render_s = 0.0
        self.render_cpu_s = 0.0
        """CPU time the render thread has used (for the benchmark's share of a core)."""
        self.tool: str | None = None
        self.goal_pub = self.node.publisher("/move_base_simple/goal", "geometry_msgs/PoseStamped")
        self.pose_pub = self.node.publisher(
            "/initialpose", "geometry_msgs/PoseWithCovarianceStamped"
        )
        self.point_pub = self.node.publisher("/clicked_point", "geometry_msgs/PointStamped")
        self.canvases = [
            CanvasDrawing(self.scene, c, f"/canvas{i}") for i, c in enumerate(canvases)
        ]
        if canvases and cmd_vel == "/cmd_vel":
            cmd_vel = canvases[0].cmd_vel
        self.cmd_pub = self.node.publisher(cmd_vel, "geometry_msgs/Twist")
        self.command = (0.0, 0.0)
        self._last_click: tuple[float, float] | None = None
        self._stop = threading.Event()
        self._lock = threading.Lock()
        self.views: dict[int, tuple[Any, ViewState]] = {}
        self.started_wall = time.time()
        self.started_ros_ns = graph.now_ns()
        self._next_status = 0.0
        camera = self.server.initial_camera
        camera.position, camera.look_at, camera.up = (
            CAMERA_POSITION,
            CAMERA_LOOK_AT,
            (0.0, 0.0, 1.0),
        )
        camera.fov = CAMERA_FOV
        self._build_gui(joint_publisher, sim)
        self._add_initial_displays(rviz)
        self.insert = world_editing(self, sim)
        self.server.on_client_connect(self._client_connected)
        self.server.on_client_disconnect(self._client_left)
        self.node.timer(0.1, self._teleop_tick)
        self.scene.on_click()(self._on_click)
        self._thread = threading.Thread(
            target=self._render_loop, name="belvedere-viewer", daemon=True
        )
        self._thread.start()

    @property
    def url(self) -> str:
        """Where to open the viewer (with ``?token=…`` when it needs one)."""
        return page_url(self.server, self.access)

    # --- GUI -----------------------------------------------------------------------------------
    def _build_gui(self, jsp: JointStatePublisher | None, sim: SimControls | None) -> None:
        gui = self.gui
        # rviz's layout: the 3D view beside the Displays panel, not under it (a software
        # renderer then draws a third fewer pixels, and the view's centre is visible).
        gui.main_panel.dock_left()
        if self.rviz is not None and self.rviz.hides_left_dock:
            gui.main_panel.minimize()  # as rviz opens that config; « opens it again
        if jsp is not None:  # `display`: the joints are what the user came for
            self._joint_panel(jsp)
        with gui.add_folder("Global Options"):
            self.frame_dropdown = gui.add_dropdown(
                "Fixed Frame", [self.fixed_frame], initial_value=self.fixed_frame
            )
            self.frame_dropdown.on_update(lambda _: self.set_fixed_frame(self.frame_dropdown.value))
            self.background = gui.add_rgb("Background Color", RvizConfig.background)
            self.background.on_update(lambda _: self.set_background(self.background.value))
            self.rate_box = gui.add_number("Frame Rate", int(self.rate_hz), min=1, max=60, step=1)
            self.rate_box.on_update(lambda _: setattr(self, "rate_hz", float(self.rate_box.value)))
        with gui.add_folder("Global Status", expand_by_default=False):
            self.status_text = gui.add_markdown("**Status: Ok**")
        if sim is not None:
            with gui.add_folder("Simulation"):
                pause = gui.add_checkbox("Paused", False)
                pause.on_update(lambda _: sim.pause(pause.value))
                gui.add_button("Step").on_click(lambda _: sim.step())
                gui.add_button("Reset").on_click(lambda _: sim.reset())
                rtf = gui.add_dropdown(
                    "Real-time factor", ["1", "2", "5", "max"], initial_value="1"
                )
                rtf.on_update(
                    lambda _: sim.set_rtf(None if rtf.value == "max" else float(rtf.value))
                )
        self.displays_folder = gui.add_folder("Displays")
        with self.displays_folder, gui.add_folder("Add display", expand_by_default=False):
            kind = gui.add_dropdown("Type", sorted(DISPLAYS), initial_value="LaserScan")
            topic = gui.add_dropdown("Topic", ["/scan"], initial_value="/scan")
            typed = gui.add_text("Or topic name", "")
            self.add_note = gui.add_markdown("")

            def offer_topics(_: Any) -> None:
                options = self.topics.of_type(DISPLAYS[kind.value].msg_type) or ["(none)"]
                topic.options = options

            kind.on_update(offer_topics)
            gui.add_button("Add").on_click(
                lambda _: self._add_from_gui(kind.value, typed.value.strip() or topic.value)
            )
            self._offer_topics = offer_topics
        with gui.add_folder("File", expand_by_default=False):
            default = str(self.rviz_path) if self.rviz_path else "belvedere.rviz"
            save_path = gui.add_text("Config file", default)
            self.save_note = gui.add_markdown("")

            def save(event: Any) -> None:
                try:
                    written = self.save_config(save_path.value.strip(), event.client)
                except BelvedereError as err:
                    self.save_note.content = f"**Not saved:** {err.describe()}"
                    return
                self.save_note.content = f"Saved `{written}`."
                self.node.logger.info("saved the rviz config %s", written)

            gui.add_button("Save Config").on_click(save)
            if self.world is not None:  # a simulated world: Gazebo's File > Save World As
                world_path = gui.add_text("World file", "saved.world")
                self.world_note = gui.add_markdown("")

                def save_world(_: Any) -> None:
                    self.world_note.content = "Saving…"
                    try:
                        written = self.save_world(world_path.value)
                    except BelvedereError as err:
                        self.world_note.content = f"**Not saved:** {err.describe()}"
                        return
                    self.world_note.content = f"Saved `{written}`."

                gui.add_button("Save World As").on_click(save_world)
        with gui.add_folder("Time", expand_by_default=False):
            self.time_texts = {
                label: gui.add_text(label, "0.00", disabled=True)
                for label in ("ROS Time", "ROS Elapsed", "Wall Time", "Wall Elapsed")
            }
        with gui.add_folder("Tools"):
            for label, tool in (
                ("2D Pose Estimate", "pose"),
                ("2D Nav Goal", "goal"),
                ("Publish Point", "point"),
            ):
                gui.add_button(label).on_click(self._tool_setter(tool))
            self.tool_text = gui.add_text("Active tool", "none", disabled=True)
        self.teleop_folder = gui.add_folder("Teleop", visible=False)
        with self.teleop_folder:
            gui.add_markdown(f"Drives `{self.cmd_pub.name}` (something subscribes to it).")
            self.max_linear = gui.add_slider("Max linear (m/s)", 0.0, 2.0, 0.05, 0.2)
            self.max_angular = gui.add_slider("Max angular (rad/s)", 0.0, 3.0, 0.05, 0.5)
            for label, cmd in (
                ("Forward", (1.0, 0.0)),
                ("Back", (-1.0, 0.0)),
                ("Left", (0.0, 1.0)),
                ("Right", (0.0, -1.0)),
                ("Stop", (0.0, 0.0)),
            ):
                gui.add_button(label).on_click(self._teleop_setter(cmd))
        self.gamepad = ViewerGamepad(self.node, gui)

    def _client_connected(self, client: Any) -> None:
        """Each tab gets its own Views panel and camera."""
        view = self.rviz.view if self.rviz is not None else None
        state = ViewState(view.cls, dict(view.properties)) if view is not None else None
        with client.gui.add_folder("Views", expand_by_default=False, order=-1):
            types = list(VIEW_TYPES)
            initial = state.cls if state is not None and state.cls in types else "(initial)"
            kind = client.gui.add_dropdown("Type", ["(initial)", *types], initial_value=initial)
            frames = ["<Fixed Frame>", *sorted(self.tf.buffer.frames())]
            target_value = state.target_frame if state is not None else "<Fixed Frame>"
            target = client.gui.add_dropdown(
                "Target Frame", sorted({*frames, target_value}), initial_value=target_value
            )

            chosen = [kind.value, target.value]

            def changed(_: Any) -> None:
                if [kind.value, target.value] == chosen:
                    return  # the browser echoing a value back: the view set elsewhere stays
                chosen[:] = [kind.value, target.value]
                if kind.value == "(initial)":
                    self.views.pop(client.client_id, None)
                    return
                current = self.views.get(client.client_id)
                props = dict(current[1].properties) if current is not None else {}
                props["Target Frame"] = target.value
                if kind.value == "rviz/TopDownOrtho":
                    props.setdefault("Scale", 50.0)
                self.views[client.client_id] = (client, ViewState(kind.value, props))

            kind.on_update(changed)
            target.on_update(changed)
            client.gui.add_button("Refresh frames").on_click(
                lambda _: setattr(target, "options", sorted({*self._frames(), target.value}))
            )
        if state is not None:
            self.views[client.client_id] = (client, state)

    def _client_left(self, client: Any) -> None:
        self.views.pop(client.client_id, None)

    def _tool_setter(self, tool: str) -> Callable[[Any], None]:
        def set_tool(_: Any) -> None:
            self.tool = tool
            self._last_click = None
            set_handle(self.tool_text, tool)

        return set_tool

    def _teleop_setter(self, cmd: tuple[float, float]) -> Callable[[Any], None]:
        def set_cmd(_: Any) -> None:
            self.command = cmd
            self._publish_command()

        return set_cmd

    def _publish_command(self) -> None:
        lin, ang = self.command
        self.cmd_pub.publish_data(
            {
                "linear": {"x": lin * self.max_linear.value},
                "angular": {"z": ang * self.max_angular.value},
            }
        )

    def _teleop_tick(self) -> None:
        listened = self.cmd_pub.wanted
        if self.teleop_folder.visible != listened:
            self.teleop_folder.visible = listened
        if self.command != (0.0, 0.0):
            self._publish_command()

    def _joint_panel(self, jsp: JointStatePublisher) -> None:
        sliders = {}
        with self.gui.add_folder("Joints"):
            for j in jsp.free:
                lo, hi = (-math.pi, math.pi)
                if j.position_range is not None:
                    lo, hi = j.position_range
                elif j.inverted_limits is not None:
                    logger.warning("%s: warning: %s", j.source, j.inverted_limits)
                slider = self.gui.add_slider(
                    j.name, lo, hi, (hi - lo) / 1000 or 0.001, jsp.positions[j.name]
                )
                slider.on_update(self._slider_callback(jsp, j.name, slider))
                sliders[j.name] = (slider, lo, hi)

            def randomize(_: Any) -> None:
                for name, (slider, lo, hi) in sliders.items():
                    set_handle(slider, float(self.graph.executor.random.uniform(lo, hi)))
                    jsp.set_position(name, slider.value)

            def center(_: Any) -> None:
                for name, (slider, lo, hi) in sliders.items():
                    set_handle(slider, (lo + hi) / 2 if not lo <= 0 <= hi else 0.0)
                    jsp.set_position(name, slider.value)

            self.gui.add_button("Randomize").on_click(randomize)
            self.gui.add_button("Center").on_click(center)
        self.sliders = {name: s for name, (s, _, _) in sliders.items()}

    @staticmethod
    def _slider_callback(jsp: JointStatePublisher, name: str, slider: Any) -> Callable[[Any], None]:
        return lambda _: jsp.set_position(name, float(slider.value))

    # --- tools ---------------------------------------------------------------------------------
    def _on_click(self, event: Any) -> None:
        if self.tool is None:
            return
        point = floor_point(event.ray_origin, event.ray_direction)
        if point is None:
            return
        yaw = 0.0
        if event.modifier == "shift" and self._last_click is not None:
            # Shift+click sets the heading of the last point towards this one.
            point, yaw = (
                self._last_click,
                math.atan2(point[1] - self._last_click[1], point[0] - self._last_click[0]),
            )
        self._last_click = point
        self.publish_tool(self.tool, point, yaw)

    def publish_tool(self, tool: str, point: tuple[float, float], yaw: float = 0.0) -> None:
        """Publish what the tool publishes at a floor point (fixed frame)."""
        stamp = self.graph.now_ns()
        header = {"stamp": [stamp // NS, stamp % NS], "frame_id": self.fixed_frame}
        x, y, z, w = quat_xyzw_from_rpy(0.0, 0.0, yaw)
        pose = {
            "position": {"x": point[0], "y": point[1]},
            "orientation": {"x": x, "y": y, "z": z, "w": w},
        }
        if tool == "goal":
            self.goal_pub.publish_data({"header": header, "pose": pose})
        elif tool == "pose":
            cov = [0.0] * 36
            cov[0] = cov[7] = 0.25
            cov[35] = 0.06853891909122467
            self.pose_pub.publish_data(
                {"header": header, "pose": {"pose": pose, "covariance": cov}}
            )
        elif tool == "point":
            self.point_pub.publish_data({"header": header, "point": {"x": point[0], "y": point[1]}})

    def close(self) -> None:
        self._stop.set()
        self._thread.join(timeout=2)
        self.windows.close()
        self.topics.close()
        with contextlib.redirect_stdout(io.StringIO()):  # viser's "Server stopped"
            self.server.stop()
