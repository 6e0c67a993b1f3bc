"""The viewer: rviz in the browser, a node on the graph, built on viser.

Rendering runs on its own thread at 30 Hz with the latest state; subscription callbacks only
keep the newest message, so the viewer never slows the graph (it drops frames instead).
"""

from __future__ import annotations

import contextlib
import io
import math
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from typing import Any, Protocol

from belvedere.description.urdf import RobotModel
from belvedere.graph import NS, Graph, Node
from belvedere.packages import PackageIndex
from belvedere.tf import (
    JointStatePublisher,
    TFError,
    Transform,
    TransformListener,
    quat_xyzw_from_rpy,
    wxyz_from_xyzw,
)
from belvedere.viewer._access import ViewerAccess, ViewerError, guard_viser
from belvedere.viewer._displays import DISPLAYS, Display
from belvedere.viewer._robot import RobotDrawing
from belvedere.viewer._rviz import RvizConfig
from belvedere.viewer._world import WorldDrawing
from belvedere.world import WorldModel

__all__ = ["SimControls", "Viewer"]


class SimControls(Protocol):
    """What a simulation offers the viewer's buttons."""

    def pause(self, paused: bool) -> None: ...
    def step(self) -> None: ...
    def reset(self) -> None: ...
    def set_rtf(self, rtf: float | None) -> None: ...


CAMERA_POSITION = (1.2, -1.6, 1.2)
CAMERA_LOOK_AT = (0.0, 0.0, 0.1)
CAMERA_FOV = math.radians(50.0)
"""The initial view: a robot-sized scene seen from the front right, above."""


def _set(handle: Any, value: Any) -> None:
    """Set a GUI handle's value (viser allows it; its type stubs say read-only)."""
    handle.value = value


def floor_point(
    origin: tuple[float, float, float], direction: tuple[float, float, float]
) -> tuple[float, float] | None:
    """Where a click ray meets the floor (z = 0), or None if it points away."""
    if abs(direction[2]) < 1e-9:
        return None
    t = -origin[2] / direction[2]
    if t < 0:
        return None
    return (origin[0] + t * direction[0], origin[1] + t * direction[1])


class Viewer:
    """A browser view of the graph: robot, TF, displays, tools, teleop, joint sliders."""

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
        rate_hz: float = 30.0,
        world: WorldModel | None = None,
        world_poses: Callable[[], Mapping[str, Transform]] | None = None,
        allow_origins: Sequence[str] = (),
        token: str | None = None,
    ) -> None:
        """``world``: models drawn in the fixed frame (Gazebo's world frame);
        ``world_poses``: where the movable ones are now (called each frame).
        ``allow_origins``: web origins besides the viewer's own page that may connect;
        ``token``: what a client must show (default: a new one when ``host`` is not loopback,
        none when it is; it is in :attr:`url`)."""
        import viser  # heavy: only the viewer uses it

        self.graph = graph
        self.access = ViewerAccess(host, allow_origins=allow_origins, token=token)
        # viser prints a banner on stdout whatever ``verbose`` says: stdout is for data (the
        # URL, echoed messages), and the banner's URL lacks the token.
        with guard_viser(self.access), contextlib.redirect_stdout(io.StringIO()):
            self.server = viser.ViserServer(host=host, port=port, verbose=False)
        if not self.access.installed:
            self.server.stop()
            msg = (
                f"viser {viser.__version__} serves its page in a way belvedere cannot guard "
                "(the origin and token checks were not installed); not serving the viewer"
            )
            raise ViewerError(msg)
        self.scene, self.gui = self.server.scene, self.server.gui
        self.node: Node = graph.create_node("belvedere_viewer")
        self.tf = TransformListener(self.node)
        self.model = model
        self.fixed_frame = (
            fixed_frame
            or (rviz.fixed_frame if rviz else None)
            or (model.root_link.name if model else "map")
        )
        self.robot = RobotDrawing(self.scene, model, packages=packages) if model else None
        self.world = WorldDrawing(self.scene, world) if world else None
        self.world_poses = world_poses
        self.displays: list[Display] = []
        self.frames: dict[str, Any] = {}
        self.rate_hz = rate_hz
        self.frames_rendered = 0
        self.last_render_s = 0.0
        self.tool: str | None = None
        self.goal_pub = self.node.publisher("/move_base_simple/goal", "geometry_msgs/PoseStamped")
        self.pose_pub = self.node.publisher(
            "/initialpose", "geometry_msgs/PoseWithCovarianceStamped"
        )
        self.point_pub = self.node.publisher("/clicked_point", "geometry_msgs/PointStamped")
        self.cmd_pub = self.node.publisher("/cmd_vel", "geometry_msgs/Twist")
        self.command = (0.0, 0.0)
        self._last_click: tuple[float, float] | None = None
        self._stop = threading.Event()
        self.scene.add_grid("/grid", width=20.0, height=20.0, cell_size=0.5, section_size=1.0)
        camera = self.server.initial_camera
        camera.position, camera.look_at, camera.up = (
            CAMERA_POSITION,
            CAMERA_LOOK_AT,
            (0.0, 0.0, 1.0),
        )
        camera.fov = CAMERA_FOV
        self._build_gui(joint_publisher, sim)
        if rviz:
            for d in rviz.displays:
                if d.kind in DISPLAYS and d.topic:
                    self.add_display(d.kind, d.topic, name=d.name)
            if rviz.unknown:
                self.node.logger.warning("rviz displays not shown: %s", ", ".join(rviz.unknown))
        self.node.timer(0.1, self._teleop_tick)
        self.scene.on_click()(self._on_click)
        self._thread = threading.Thread(
            target=self._render_loop, name="belvedere-viewer", daemon=True
        )
        self._thread.start()

    @property
    def url(self) -> str:
        """Where to open the viewer (with ``?token=…`` when it needs one)."""
        base = f"http://{self.server.get_host()}:{self.server.get_port()}"
        token = self.access.token
        return f"{base}/?token={token}" if token else base

    # --- GUI -----------------------------------------------------------------------------------
    def _build_gui(self, jsp: JointStatePublisher | None, sim: SimControls | None) -> None:
        gui = self.gui
        with gui.add_folder("Global"):
            self.frame_dropdown = gui.add_dropdown(
                "Fixed frame", [self.fixed_frame], initial_value=self.fixed_frame
            )
            self.frame_dropdown.on_update(
                lambda _: setattr(self, "fixed_frame", self.frame_dropdown.value)
            )
            self.show_frames = gui.add_checkbox("TF frames", False)
            self.frame_scale = gui.add_slider("TF scale", 0.05, 1.0, 0.05, 0.2)
            if self.robot:
                collisions = gui.add_checkbox("Collision geometry", False)
                collisions.on_update(
                    lambda _: self.robot.show_collisions(collisions.value) if self.robot else None
                )
            self.time_text = gui.add_text("Time", "0.000", disabled=True)
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
        with gui.add_folder("Displays"):
            kind = gui.add_dropdown("Type", sorted(DISPLAYS), initial_value="LaserScan")
            topic = gui.add_text("Topic", "/scan")
            gui.add_button("Add display").on_click(
                lambda _: self._add_from_gui(kind.value, topic.value)
            )
        with gui.add_folder("Tools"):
            for label, tool in (
                ("2D Pose Estimate", "pose"),
                ("2D Nav Goal", "goal"),
                ("Publish Point", "point"),
            ):
                gui.add_button(label).on_click(self._tool_setter(tool))
            self.tool_text = gui.add_text("Active tool", "none", disabled=True)
        with gui.add_folder("Teleop"):
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
        if jsp is not None:
            self._joint_panel(jsp)

    def _tool_setter(self, tool: str) -> Callable[[Any], None]:
        def set_tool(_: Any) -> None:
            self.tool = tool
            self._last_click = None
            _set(self.tool_text, tool)

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
        if self.command != (0.0, 0.0):
            self._publish_command()

    def _joint_panel(self, jsp: JointStatePublisher) -> None:
        sliders = {}
        with self.gui.add_folder("Joints"):
            for j in jsp.free:
                lo, hi = (-math.pi, math.pi)
                if j.limit is not None and j.type != "continuous":
                    lo, hi = j.limit.lower, j.limit.upper
                slider = self.gui.add_slider(
                    j.name, lo, hi, (hi - lo) / 1000 or 0.001, jsp.positions[j.name]
                )
                slider.on_update(self._slider_callback(jsp, j.name, slider))
                sliders[j.name] = (slider, lo, hi)

            def randomize(_: Any) -> None:
                for name, (slider, lo, hi) in sliders.items():
                    _set(slider, float(self.graph.executor.random.uniform(lo, hi)))
                    jsp.set_position(name, slider.value)

            def center(_: Any) -> None:
                for name, (slider, lo, hi) in sliders.items():
                    _set(slider, (lo + hi) / 2 if not lo <= 0 <= hi else 0.0)
                    jsp.set_position(name, slider.value)

            self.gui.add_button("Randomize").on_click(randomize)
            self.gui.add_button("Center").on_click(center)
        self.sliders = {name: s for name, (s, _, _) in sliders.items()}

    @staticmethod
    def _slider_callback(jsp: JointStatePublisher, name: str, slider: Any) -> Callable[[Any], None]:
        return lambda _: jsp.set_position(name, float(slider.value))

    def _add_from_gui(self, kind: str, topic: str) -> None:
        self.add_display(kind, topic)

    # --- displays and tools ----------------------------------------------------------------------
    def add_display(self, kind: str, topic: str, *, name: str | None = None) -> Display:
        cls = DISPLAYS[kind]
        display = cls(
            self.node,
            self.scene,
            self.gui,
            name or f"{kind}_{len(self.displays)}",
            topic,
            self.tf.buffer,
        )
        self.displays.append(display)
        return display

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

    # --- rendering -------------------------------------------------------------------------------
    def _render_loop(self) -> None:
        period = 1.0 / self.rate_hz
        next_at = time.monotonic()
        while not self._stop.is_set():
            start = time.monotonic()
            try:
                self.render_once()
            except Exception:
                self.node.logger.exception("viewer frame failed")
            self.last_render_s = time.monotonic() - start
            next_at = max(next_at + period, time.monotonic())  # drop frames when late
            self._stop.wait(max(0.0, next_at - time.monotonic()))

    def render_once(self) -> None:
        fixed = self.fixed_frame
        buffer = self.tf.buffer
        if self.robot is not None:
            for link in self.robot.links:
                try:
                    t = buffer.lookup_transform(fixed, link)
                except TFError:
                    continue
                self.robot.set_link_pose(link, t.translation, t.quat_xyzw)
        frames = sorted(buffer.frames() | {fixed})
        if list(self.frame_dropdown.options) != frames:
            self.frame_dropdown.options = frames
        if self.show_frames.value:
            for frame in frames:
                try:
                    t = buffer.lookup_transform(fixed, frame)
                except TFError:
                    continue
                handle = self.frames.get(frame)
                if handle is None:
                    handle = self.frames[frame] = self.scene.add_frame(
                        f"/tf/{frame}", axes_length=0.2, axes_radius=0.005
                    )
                    self.scene.add_label(f"/tf/{frame}/label", frame)
                handle.position = t.translation
                handle.wxyz = wxyz_from_xyzw(t.quat_xyzw)
                handle.scale = float(self.frame_scale.value) / 0.2
                handle.visible = True
        else:
            for handle in self.frames.values():
                handle.visible = False
        if self.world is not None and self.world_poses is not None:
            self.world.update(self.world_poses())
        for display in self.displays:
            display.render(fixed)
        _set(self.time_text, f"{self.graph.now_ns() / NS:.3f}")
        self.frames_rendered += 1

    def close(self) -> None:
        self._stop.set()
        self._thread.join(timeout=2)
        with contextlib.redirect_stdout(io.StringIO()):  # viser's "Server stopped"
            self.server.stop()
