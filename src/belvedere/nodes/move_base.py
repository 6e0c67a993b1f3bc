"""move_base: the ``move_base`` action over two costmaps, a global and a local planner, and
the recovery behaviours, as ROS 1's move_base runs them.

In: goals on the ``move_base`` action (``move_base_msgs/MoveBaseAction``) and on
``move_base_simple/goal``; the robot's pose from TF (each costmap's global frame → its
``robot_base_frame``); its velocity from ``odom``. Out: ``cmd_vel``, ``~current_goal``, the
global plan (``~<Planner>/plan``), the local planner's ``~<Planner>/local_plan`` and
``global_plan``, the costmaps (``~global_costmap/…``, ``~local_costmap/…``); services
``~make_plan`` and ``~clear_costmaps``.

Each control cycle (``controller_frequency``, graph time) follows move_base's states:
planning (a plan from the robot to the goal; none for ``planner_patience`` → recoveries),
controlling (the local planner's command, the goal reached within its tolerances → succeeded;
no command for ``controller_patience`` or no progress of ``oscillation_distance`` in
``oscillation_timeout`` → recoveries) and clearing (``~recovery_behaviors``, a list of
``{name, type}`` with each behaviour's parameters under ``~<name>/``; by default conservative
reset, rotate_recovery's turn in place if ``clearing_rotation_allowed``, aggressive reset,
the turn again; all tried → aborted). With
``planner_frequency`` > 0 the plan is remade that often while controlling. The planners run on
the graph's executor thread: in simulated time nothing moves while they think, so runs are
deterministic.
"""

from __future__ import annotations

import contextlib
from collections.abc import Mapping
from typing import Any

import numpy as np

from belvedere.errors import BelvedereError
from belvedere.graph import NS, ActionServer, GoalHandle, Node
from belvedere.msgs import message_from_data
from belvedere.nav.local import DWAPlannerROS, LocalPlanner, make_local_planner
from belvedere.nav.planners import GlobalPlanner, UnknownPluginError, make_global_planner
from belvedere.nav.recovery import (
    ROTATE,
    ClearCostmapParams,
    RecoveryListError,
    RotateRecovery,
    RotateRecoveryParams,
    recovery_behaviors,
)
from belvedere.nodes import _reconfigure as reconfigure
from belvedere.nodes._costmap import Costmap2DROS
from belvedere.nodes._costmap_reconfigure import serve_costmap
from belvedere.nodes._move_base import Cycle, Floats, MoveBaseParams, State, Trigger
from belvedere.nodes._registry import (
    NodeSpec,
    Session,
    Starter,
    StartError,
    stopping_on_bad_values,
)
from belvedere.ros1.dynamic_reconfigure.graph_server import GraphServer
from belvedere.tf import TFBuffer, TransformListener
from belvedere.yamlfile import load_yaml_file

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE", "MoveBaseParams"]

PACKAGE = "move_base"


def _short(plugin: str) -> str:
    """A plugin's parameter namespace: ``navfn/NavfnROS`` → ``NavfnROS``."""
    return plugin.rsplit("/", 1)[-1]


class _MoveBase(Cycle):
    def __init__(self, node: Node, session: Session, spec: NodeSpec) -> None:
        self.node = node
        private = node.get_param("~", {})
        self.params = MoveBaseParams.from_mapping(private if isinstance(private, dict) else {})
        p = self.params
        self.buffer = TFBuffer()
        TransformListener(node, self.buffer)
        self.global_costmap = Costmap2DROS(node, "global_costmap", self.buffer)
        self.local_costmap = Costmap2DROS(node, "local_costmap", self.buffer)
        self.global_planner = self._plugin(session, spec, "base_global_planner", private)
        self.local_planner = self._plugin(session, spec, "base_local_planner", private)
        global_name, local_name = _short(p.base_global_planner), _short(p.base_local_planner)
        self.cmd_pub = node.publisher("cmd_vel", "geometry_msgs/Twist", queue_size=1)
        self.goal_pub = node.publisher("~current_goal", "geometry_msgs/PoseStamped", queue_size=1)
        self.plan_pub = node.publisher(f"~{global_name}/plan", "nav_msgs/Path", queue_size=1)
        self.local_plan_pub = node.publisher(
            f"~{local_name}/local_plan", "nav_msgs/Path", queue_size=1
        )
        self.followed_pub = node.publisher(
            f"~{local_name}/global_plan", "nav_msgs/Path", queue_size=1
        )
        self.velocity = np.zeros(3)
        node.subscribe("odom", "nav_msgs/Odometry", self._on_odom, queue_size=1)
        self.server = ActionServer(node, "move_base", "move_base_msgs/MoveBase", self._execute)
        self.goal_client = node.publisher(
            "move_base/goal", "move_base_msgs/MoveBaseActionGoal", queue_size=1
        )
        node.subscribe("move_base_simple/goal", "geometry_msgs/PoseStamped", self._on_simple_goal)
        node.service("~make_plan", "nav_msgs/GetPlan", self._on_make_plan)
        node.service("~clear_costmaps", "std_srvs/Empty", self._on_clear_costmaps)
        self.handle: GoalHandle | None = None
        self.goal: Floats | None = None
        self.state = State.PLANNING
        self.plan: Floats | None = None
        self.plan_to_local: tuple[float, float, float] | None = None
        self.recovery_index = 0
        self.recovery_trigger = Trigger.PLANNING
        self.planning_since = 0
        self.last_valid_control = 0
        self.last_plan_at = 0
        self.retries = 0
        self.oscillation_pose: Floats | None = None
        self.oscillation_since = 0
        self.rotation: RotateRecovery | None = None
        self.rotating = ""
        self.recoveries = self._recoveries(
            session, spec, private if isinstance(private, dict) else {}
        )
        self._warned: set[str] = set()
        self.global_costmap.start()
        self.local_costmap.start()
        if p.shutdown_costmaps:
            self.global_costmap.stop()
            self.local_costmap.stop()
        self.timer = node.timer(1.0 / p.controller_frequency, self._cycle)
        self._serve_reconfigure(local_name)

    # --- dynamic_reconfigure (rqt_reconfigure, dynparam) ---------------------------------------
    def _serve_reconfigure(self, local_name: str) -> None:
        own = reconfigure.current(reconfigure.MOVE_BASE, self.params)
        GraphServer(self.node, reconfigure.MOVE_BASE, own, self._reconfigure)
        local = (
            reconfigure.DWA_PLANNER
            if isinstance(self.local_planner, DWAPlannerROS)
            else reconfigure.TRAJECTORY_PLANNER
        )
        values = reconfigure.current(local, self.local_planner.params)
        GraphServer(self.node, local, values, self._reconfigure_local, ns=f"~{local_name}")
        serve_costmap(self.global_costmap)
        serve_costmap(self.local_costmap)

    def _reconfigure(self, config: dict[str, Any], level: int) -> None:
        for plugin in ("base_global_planner", "base_local_planner"):
            if config[plugin] != getattr(self.params, plugin):
                message = f"{plugin} cannot change while move_base runs (restart it)"
                raise ValueError(message)
        params = MoveBaseParams.from_mapping({**self.params.__dict__, **config})
        if params.controller_frequency != self.params.controller_frequency:
            self.timer.cancel()
            self.timer = self.node.timer(1.0 / params.controller_frequency, self._cycle)
        self.params = params

    def _reconfigure_local(self, config: dict[str, Any], level: int) -> None:
        params = reconfigure.replaced(self.local_planner.params, config)
        params.check()
        self.local_planner = type(self.local_planner)(params)
        self.plan_to_local = None  # the new planner is handed the plan on the next cycle

    def _plugin(self, session: Session, spec: NodeSpec, param: str, private: Any) -> Any:
        p = self.params
        name = p.base_global_planner if param == "base_global_planner" else p.base_local_planner
        values = private.get(_short(name), {}) if isinstance(private, dict) else {}
        values = values if isinstance(values, dict) else {}
        try:
            if param == "base_global_planner":
                planner: GlobalPlanner | LocalPlanner = make_global_planner(name, values)
            else:
                merged = {"controller_frequency": p.controller_frequency, **values}
                planner = make_local_planner(name, merged)
        except UnknownPluginError as err:
            where = session.param_source(f"{spec.full_name}/{param}") or spec.source
            message = f"{spec.full_name}: parameter {param}: {err}"
            raise StartError(message, where) from None
        return planner

    def _recoveries(
        self, session: Session, spec: NodeSpec, private: Mapping[str, Any]
    ) -> list[tuple[str, ClearCostmapParams | RotateRecoveryParams]]:
        """The recovery behaviours in the order move_base runs them, each with its
        parameters (``~<name>/``): ``~recovery_behaviors`` when given, else move_base's
        defaults (conservative reset, a turn if ``clearing_rotation_allowed``, aggressive
        reset, the turn again)."""
        blp = private.get("TrajectoryPlannerROS", {})
        blp = blp if isinstance(blp, dict) else {}

        def own(name: str) -> dict[str, Any]:
            values = private.get(name, {})
            return values if isinstance(values, dict) else {}

        if "recovery_behaviors" not in private:
            rotate = RotateRecoveryParams.from_mapping(own("rotate_recovery"), blp)
            clearing = self._clearing_params(private)
            turn: list[tuple[str, ClearCostmapParams | RotateRecoveryParams]] = (
                [("rotate_recovery", rotate)] if self.params.clearing_rotation_allowed else []
            )
            return [
                ("conservative_reset", clearing["conservative_reset"]),
                *turn,
                ("aggressive_reset", clearing["aggressive_reset"]),
                *turn,
            ]
        try:
            listed = recovery_behaviors(private["recovery_behaviors"])
        except RecoveryListError as err:
            where = session.param_source(f"{spec.full_name}/recovery_behaviors") or spec.source
            if where is not None and where.path.endswith((".yaml", ".yml")) and err.keys:
                # (a file changed since the launch read it keeps the list's line)
                with contextlib.suppress(BelvedereError):
                    where = load_yaml_file(where.path).location_within(where, *err.keys)
            message = f"{spec.full_name}: parameter {err}"
            raise StartError(message, where) from None
        out: list[tuple[str, ClearCostmapParams | RotateRecoveryParams]] = []
        for behaviour in listed:
            if behaviour.type == ROTATE:
                out.append(
                    (behaviour.name, RotateRecoveryParams.from_mapping(own(behaviour.name), blp))
                )
            else:
                out.append(
                    (
                        behaviour.name,
                        ClearCostmapParams.from_mapping(behaviour.name, own(behaviour.name)),
                    )
                )
        return out

    def _clearing_params(self, private: Mapping[str, Any]) -> dict[str, ClearCostmapParams]:
        """The two default clearing recoveries' parameters. As move_base does for its
        defaults, their ``reset_distance`` is ``conservative_reset_dist`` and four times
        ``~local_costmap/circumscribed_radius`` (a parameter of its own, default 0.46 m, not
        the costmap's radius)."""
        local = private.get("local_costmap", {})
        radius = local.get("circumscribed_radius", 0.46) if isinstance(local, dict) else 0.46
        if isinstance(radius, bool) or not isinstance(radius, int | float):
            message = (
                f"parameter local_costmap/circumscribed_radius must be a number, got {radius!r}"
            )
            raise ValueError(message)
        distances = {
            "conservative_reset": self.params.conservative_reset_dist,
            "aggressive_reset": 4.0 * float(radius),
        }
        out = {}
        for name, distance in distances.items():
            own = private.get(name, {})
            out[name] = ClearCostmapParams.from_mapping(
                name, own if isinstance(own, dict) else {}, distance
            )
        return out

    # --- inputs ------------------------------------------------------------------------------
    def _on_odom(self, msg: Any) -> None:
        t = msg.twist.twist
        self.velocity = np.array([t.linear.x, t.linear.y, t.angular.z])

    def _on_simple_goal(self, msg: Any) -> None:
        # as move_base: a simple goal becomes a goal on its own action
        now = self.node.now_ns()
        goal = message_from_data(
            "move_base_msgs/MoveBaseActionGoal",
            {
                "header": {"stamp": {"sec": now // NS, "nanosec": now % NS}},
                "goal_id": {"id": f"{self.node.full_name}-simple-{now}"},
            },
        )
        goal.goal.target_pose = msg
        self.goal_client.publish(goal)

    def _execute(self, handle: GoalHandle) -> None:
        target = handle.goal.target_pose
        goal = self._in_global_frame(target)
        if goal is None:
            handle.abort(text="the goal's frame cannot be transformed to the global frame")
            return
        self.handle = handle
        self.goal = goal
        self._publish_goal()
        self._start_planning()
        self.recovery_index = 0
        self.oscillation_pose = None


EXECUTABLES: dict[str, Starter] = {
    "move_base": stopping_on_bad_values(lambda session, spec, node: _MoveBase(node, session, spec))
}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
