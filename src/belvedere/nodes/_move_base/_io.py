"""What move_base reads from TF and sends: goals in the global frame, ``cmd_vel``, the goal
and the paths, and its services ``~make_plan`` and ``~clear_costmaps``."""

from __future__ import annotations

import logging
import math
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from belvedere.graph import GoalHandle, Node, Publisher
from belvedere.msgs import build, message_from_data, types
from belvedere.nav.planners import NoPathError
from belvedere.nodes._costmap import Costmap2DROS
from belvedere.nodes._move_base._params import MoveBaseParams
from belvedere.nodes._planar import yaw_of
from belvedere.tf import TFBuffer, TFError

__all__ = ["Floats", "NodeIO"]

logger = logging.getLogger("belvedere.nodes.move_base")

Floats = npt.NDArray[np.float64]


def _pose_data(x: float, y: float, yaw: float) -> dict[str, Any]:
    """A planar pose as ``geometry_msgs/Pose`` data."""
    return {
        "position": {"x": float(x), "y": float(y), "z": 0.0},
        "orientation": {"z": math.sin(yaw / 2), "w": math.cos(yaw / 2)},
    }


def _transform(poses: Floats, transform: tuple[float, float, float]) -> npt.NDArray[np.float64]:
    """(N, 3) poses moved by a planar transform (x, y, yaw)."""
    x, y, th = transform
    c, s = math.cos(th), math.sin(th)
    out = np.empty_like(poses)
    out[:, 0] = x + c * poses[:, 0] - s * poses[:, 1]
    out[:, 1] = y + s * poses[:, 0] + c * poses[:, 1]
    out[:, 2] = poses[:, 2] + th
    return out


class NodeIO:
    """The node's part that talks to the graph (a base of the node, over its state)."""

    if TYPE_CHECKING:
        node: Node
        params: MoveBaseParams
        buffer: TFBuffer
        global_costmap: Costmap2DROS
        local_costmap: Costmap2DROS
        global_planner: Any
        cmd_pub: Publisher
        goal_pub: Publisher
        handle: GoalHandle | None
        goal: Floats | None
        plan: Floats | None
        _warned: set[str]

    # --- frames --------------------------------------------------------------------------------
    def _warn_once(self, key: str, text: str) -> None:
        if key not in self._warned:
            self._warned.add(key)
            logger.warning("%s: %s", self.node.full_name, text)

    def _in_global_frame(self, pose_stamped: Any) -> Floats | None:
        frame = pose_stamped.header.frame_id.lstrip("/") or self.global_costmap.global_frame
        p, q = pose_stamped.pose.position, pose_stamped.pose.orientation
        if not all(math.isfinite(v) for v in (p.x, p.y, q.x, q.y, q.z, q.w)):
            self._warn_once("nan", "a goal with NaN or infinite values was refused")
            return None
        if abs(math.sqrt(q.x**2 + q.y**2 + q.z**2 + q.w**2) - 1.0) > 0.01:
            self._warn_once("quat", "a goal whose orientation is not a unit quaternion was refused")
            return None
        pose: Floats = np.array([[p.x, p.y, yaw_of((q.x, q.y, q.z, q.w))]], dtype=np.float64)
        if frame == self.global_costmap.global_frame:
            same: Floats = pose[0].copy()
            return same
        moved = self._planar(self.global_costmap.global_frame, frame)
        if moved is None:
            return None
        placed: Floats = _transform(pose, moved)[0]
        return placed

    def _planar(self, target: str, source: str) -> tuple[float, float, float] | None:
        try:
            _, t, q = self.buffer.lookup(target, source, 0)
        except TFError as err:
            self._warn_once(f"tf {target} {source}", err.message)
            return None
        return (float(t[0]), float(t[1]), yaw_of(q))

    # --- outputs -------------------------------------------------------------------------------
    def _send(self, vx: float, vy: float, vth: float) -> None:
        self.cmd_pub.publish_data(
            {"linear": {"x": vx, "y": vy, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": vth}}
        )

    def _stop(self) -> None:
        self._send(0.0, 0.0, 0.0)

    def _end(self, finish: Any) -> None:
        self.handle = None
        self.goal = None
        self.plan = None
        if self.params.shutdown_costmaps:
            self.global_costmap.stop()
            self.local_costmap.stop()
        finish()

    def _publish_goal(self) -> None:
        assert self.goal is not None
        path = self._path(self.goal[None, :], self.global_costmap.global_frame)
        self.goal_pub.publish(path.poses[0])

    def _publish_path(self, publisher: Any, poses: Floats, frame: str) -> None:
        publisher.publish(self._path(poses, frame))

    def _path(self, poses: Floats, frame: str) -> Any:
        """(N, 3) poses as a ``nav_msgs/Path`` stamped now."""
        header = build.header(self.node.now_ns(), frame)
        pose_stamped = types().cls("geometry_msgs/PoseStamped")
        stamped = [
            pose_stamped(header, message_from_data("geometry_msgs/Pose", _pose_data(x, y, yaw)))
            for x, y, yaw in np.asarray(poses, dtype=np.float64).reshape(-1, 3)
        ]
        return types().cls("nav_msgs/Path")(header, stamped)

    # --- services ------------------------------------------------------------------------------
    def _on_make_plan(self, request: Any) -> Any:
        response = types().cls("nav_msgs/srv/GetPlan_Response")
        goal = self._in_global_frame(request.goal)
        start_frame = request.start.header.frame_id
        start = (
            self._in_global_frame(request.start)
            if start_frame
            else self.global_costmap.robot_pose()
        )
        frame = self.global_costmap.global_frame
        empty = self._path(np.zeros((0, 3)), frame)
        if goal is None or start is None:
            return response(empty)
        self.global_costmap.update_now()
        try:
            plan = self.global_planner.plan(self.global_costmap.grid(), start, goal)
        except NoPathError:
            return response(empty)
        return response(self._path(plan, frame))

    def _on_clear_costmaps(self, request: Any) -> Any:
        del request
        self.global_costmap.reset()
        self.local_costmap.reset()
        return types().cls("std_srvs/srv/Empty_Response")()
