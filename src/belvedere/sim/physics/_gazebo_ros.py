"""gazebo_ros's ROS interface to the simulation: ``/gazebo/model_states`` and
``/gazebo/link_states`` (every physics step, while someone listens), and the services
``spawn_urdf_model``, ``spawn_sdf_model``, ``delete_model``, ``get_model_state``,
``set_model_state``, ``reset_world``, ``reset_simulation``, ``pause_physics``,
``unpause_physics`` and ``get_physics_properties`` — plus the ``spawn_model`` tool — and
``save_world`` (belvedere's: gzclient's File > Save World As as a service).
"""

from __future__ import annotations

import argparse
import logging
from collections.abc import Sequence
from typing import Any

import numpy as np

from belvedere.bounded import TEXT_FILE_BYTES, LimitError, read_regular_text
from belvedere.description.urdf import Pose, RobotModel
from belvedere.errors import BelvedereError
from belvedere.graph import Node
from belvedere.msgs import message_from_data
from belvedere.packages import PackageIndex
from belvedere.sim import SAVE_WORLD, SAVE_WORLD_TYPE
from belvedere.sim.physics._engine import quat_xyzw
from belvedere.sim.physics._save import save_world
from belvedere.sim.physics._simulation import PhysicsSimulation
from belvedere.tf import quat_xyzw_from_rpy
from belvedere.world import read_world_string
from belvedere.world._poses import quat_xyzw_to_rpy

__all__ = [
    "SAVE_WORLD",
    "SAVE_WORLD_TYPE",
    "GazeboRos",
    "name_taken",
    "parse_spawn_args",
    "spawn_model",
]

logger = logging.getLogger("belvedere.physics")


def name_taken(name: str) -> str:
    """Gazebo's words when asked to spawn a model under a name the world has."""
    return f"SpawnModel: Failure - model name {name} already exist."


def _pose_data(m: Any) -> dict[str, Any]:
    x, y, z, w = quat_xyzw(m)
    return {
        "position": {"x": float(m[0, 3]), "y": float(m[1, 3]), "z": float(m[2, 3])},
        "orientation": {"x": x, "y": y, "z": z, "w": w},
    }


def _pose_from_msg(pose: Any) -> Pose:
    o = pose.orientation
    if (o.x, o.y, o.z, o.w) == (0.0, 0.0, 0.0, 0.0):
        rpy = (0.0, 0.0, 0.0)
    else:
        rpy = quat_xyzw_to_rpy(o.x, o.y, o.z, o.w)
    return Pose((pose.position.x, pose.position.y, pose.position.z), rpy)


class GazeboRos:
    """The ``/gazebo`` node of a :class:`PhysicsSimulation`."""

    def __init__(self, sim: PhysicsSimulation, *, packages: PackageIndex | None = None) -> None:
        self.sim = sim
        self.packages = packages
        node = sim.graph.create_node("gazebo", namespace="/gazebo_ros")
        self.node = node
        self.model_pub = node.publisher(
            "/gazebo/model_states", "gazebo_msgs/ModelStates", queue_size=1
        )
        self.link_pub = node.publisher(
            "/gazebo/link_states", "gazebo_msgs/LinkStates", queue_size=1
        )
        for name, srv, handler in (
            ("spawn_urdf_model", "gazebo_msgs/SpawnModel", self._spawn_urdf),
            ("spawn_sdf_model", "gazebo_msgs/SpawnModel", self._spawn_sdf),
            ("delete_model", "gazebo_msgs/DeleteModel", self._delete),
            ("get_model_state", "gazebo_msgs/GetModelState", self._get_state),
            ("set_model_state", "gazebo_msgs/SetModelState", self._set_state),
            ("reset_world", "std_srvs/Empty", self._reset_world),
            ("reset_simulation", "std_srvs/Empty", self._reset_world),
            ("pause_physics", "std_srvs/Empty", lambda _: self._pause(True)),
            ("unpause_physics", "std_srvs/Empty", lambda _: self._pause(False)),
            ("get_physics_properties", "gazebo_msgs/GetPhysicsProperties", self._physics),
        ):
            node.service(f"/gazebo/{name}", srv, handler)
        # On a thread of its own: the file is written while the simulation steps on.
        node.service(SAVE_WORLD, SAVE_WORLD_TYPE, self._save_world, threaded=True)
        sim.after_step.append(self._publish_states)
        sim.every_step.append(lambda: self.model_pub.wanted or self.link_pub.wanted)

    # --- topics ----------------------------------------------------------------------------------
    def _publish_states(self) -> None:
        if self.model_pub.wanted:
            models = self.sim.model_names()
            self.model_pub.publish(
                message_from_data(
                    "gazebo_msgs/ModelStates",
                    {
                        "name": models,
                        "pose": [_pose_data(self.sim.model_pose(n)) for n in models],
                        "twist": [{} for _ in models],
                    },
                )
            )
        if self.link_pub.wanted:
            engine = self.sim.engine
            m = engine.m
            names: list[str] = []
            poses: list[dict[str, Any]] = []
            for body in range(1, m.nbody):
                names.append(m.body(body).name.replace("/", "::"))
                poses.append(_pose_data(engine.body_pose(body)))
            self.link_pub.publish(
                message_from_data(
                    "gazebo_msgs/LinkStates",
                    {"name": names, "pose": poses, "twist": [{} for _ in names]},
                )
            )

    # --- services --------------------------------------------------------------------------------
    def _spawn_urdf(self, req: Any) -> dict[str, Any]:
        if req.model_name in self.sim.model_names():
            return {"success": False, "status_message": name_taken(req.model_name)}
        try:
            model = RobotModel.from_string(req.model_xml, path=f"<{req.model_name}>")
            self.sim.spawn(
                model,
                name=req.model_name or model.name,
                pose=_pose_from_msg(req.initial_pose),
                packages=self.packages,
                robot_namespace=req.robot_namespace,
            )
        except BelvedereError as err:
            return {"success": False, "status_message": _spawn_failure(err)}
        return {"success": True, "status_message": "SpawnModel: Successfully spawned entity"}

    def _spawn_sdf(self, req: Any) -> dict[str, Any]:
        if req.model_name in self.sim.model_names():
            return {"success": False, "status_message": name_taken(req.model_name)}
        try:
            world = read_world_string(req.model_xml, f"<{req.model_name}>", packages=self.packages)
            if len(world.models) != 1:
                msg = f"expected one <model>, found {len(world.models)}"
                raise BelvedereError(msg)
            self.sim.add_model(
                world.models[0], name=req.model_name, pose=_pose_from_msg(req.initial_pose)
            )
        except BelvedereError as err:
            return {"success": False, "status_message": _spawn_failure(err)}
        return {"success": True, "status_message": "SpawnModel: Successfully spawned entity"}

    def _delete(self, req: Any) -> dict[str, Any]:
        try:
            self.sim.delete(req.model_name)
        except KeyError as err:
            return {"success": False, "status_message": f"DeleteModel: {err.args[0]}"}
        return {"success": True, "status_message": "DeleteModel: successfully deleted model"}

    def _get_state(self, req: Any) -> dict[str, Any]:
        now = self.sim.graph.now_ns()
        try:
            pose = self.sim.model_pose(req.model_name)
            twist = self.sim.model_twist(req.model_name)
            if req.relative_entity_name not in ("", "world", "map"):
                base = self.sim.model_pose(req.relative_entity_name)
                pose = np.linalg.inv(base) @ pose
        except KeyError as err:
            return {"success": False, "status_message": f"GetModelState: {err.args[0]}"}
        return {
            "header": {"stamp": [now // 1_000_000_000, now % 1_000_000_000]},
            "pose": _pose_data(pose),
            "twist": {
                "angular": dict(zip("xyz", map(float, twist[:3]), strict=True)),
                "linear": dict(zip("xyz", map(float, twist[3:]), strict=True)),
            },
            "success": True,
            "status_message": "GetModelState: got properties",
        }

    def _set_state(self, req: Any) -> dict[str, Any]:
        state = req.model_state
        values = [
            state.pose.position.x,
            state.pose.position.y,
            state.pose.position.z,
            state.pose.orientation.x,
            state.pose.orientation.y,
            state.pose.orientation.z,
            state.pose.orientation.w,
        ]
        if not all(np.isfinite(values)):
            return {"success": False, "status_message": "SetModelState: pose is not finite"}
        try:
            self.sim.set_model_pose(state.model_name, _pose_from_msg(state.pose))
        except KeyError as err:
            return {"success": False, "status_message": f"SetModelState: {err.args[0]}"}
        return {"success": True, "status_message": "SetModelState: set model state done"}

    def _save_world(self, req: Any) -> dict[str, Any]:
        try:
            written = save_world(self.sim, req.path, wait_for_start=True)
        except BelvedereError as err:
            why = err.describe().removeprefix("error: ")
            return {"success": False, "status_message": f"SaveWorld: {why}", "path": ""}
        logger.info("saved the world to %s", written)
        return {
            "success": True,
            "status_message": f"SaveWorld: saved {written}",
            "path": str(written),
        }

    def _reset_world(self, _: Any) -> dict[str, Any]:
        self.sim.reset_world()
        return {}

    def _pause(self, paused: bool) -> dict[str, Any]:
        self.sim.paused = paused
        return {}

    def _physics(self, _: Any) -> dict[str, Any]:
        physics = self.sim.engine.physics
        gx, gy, gz = physics.gravity
        return {
            "time_step": physics.max_step_size,
            "pause": self.sim.paused,
            "max_update_rate": physics.real_time_update_rate,
            "gravity": {"x": gx, "y": gy, "z": gz},
            "ode_config": {"sor_pgs_iters": 50, "sor_pgs_w": 1.3, "max_contacts": 20},
            "success": True,
            "status_message": "GetPhysicsProperties: got properties",
        }


def parse_spawn_args(argv: Sequence[str]) -> argparse.Namespace:
    """gazebo_ros's ``spawn_model`` command line."""
    p = argparse.ArgumentParser(prog="spawn_model", add_help=False, exit_on_error=False)
    source = p.add_mutually_exclusive_group()
    p.add_argument("-urdf", action="store_true")
    p.add_argument("-sdf", action="store_true")
    source.add_argument("-param")
    source.add_argument("-file")
    source.add_argument("-database")
    p.add_argument("-model", required=True)
    for axis in ("x", "y", "z", "R", "P", "Y"):
        p.add_argument(f"-{axis}", type=float, default=0.0)
    p.add_argument("-reference_frame", default="")
    p.add_argument("-gazebo_namespace", default="/gazebo")
    p.add_argument("-robot_namespace", default=None)
    p.add_argument("-unpause", action="store_true")
    p.add_argument("-wait")
    p.add_argument("-J", nargs=2, action="append", default=[])
    try:
        args, _ = p.parse_known_args(list(argv))
    except (argparse.ArgumentError, SystemExit) as err:
        msg = f"spawn_model: {err}"
        raise BelvedereError(msg) from None
    if args.database:
        msg = "spawn_model -database: belvedere never downloads models"
        raise BelvedereError(msg, hint="use -file or -param, or put the model in ~/.gazebo/models")
    return args


def _spawn_failure(err: BelvedereError) -> str:
    """Gazebo's ``SpawnModel: Failure - …`` with our account of it (its place in the model's
    text when it has one); the caller prints it as its own error."""
    text = err.describe()
    return "SpawnModel: Failure - " + text.removeprefix("error: ")


def spawn_model(node: Node, argv: Sequence[str]) -> Any:
    """Run ``spawn_model`` against the simulation's services: read the model from a
    parameter or a file and call ``spawn_{urdf,sdf}_model``."""
    args = parse_spawn_args(argv)
    if args.param:
        xml = node.get_param(args.param, None)
        if xml is None:
            msg = f"spawn_model: parameter {args.param!r} is not set"
            raise BelvedereError(msg, hint="load the robot description first")
    elif args.file:
        try:
            xml = read_regular_text(args.file, limit=TEXT_FILE_BYTES, what="")
        except LimitError as err:
            msg = f"spawn_model: {err.message}"
            raise BelvedereError(msg) from None
    else:
        msg = "spawn_model: give -param NAME or -file PATH"
        raise BelvedereError(msg)
    kind = "sdf" if args.sdf else "urdf"
    # spawn_model's default is rospy.get_namespace(): the spawner's own namespace, so a
    # spawner in <group ns="robot_1"> puts the robot's plugins under /robot_1.
    robot_namespace = args.robot_namespace
    if robot_namespace is None:
        robot_namespace = node.namespace.rstrip("/") + "/"
    qx, qy, qz, qw = quat_xyzw_from_rpy(args.R, args.P, args.Y)
    response = node.call_service(
        f"{args.gazebo_namespace.rstrip('/')}/spawn_{kind}_model",
        "gazebo_msgs/SpawnModel",
        {
            "model_name": args.model,
            "model_xml": str(xml),
            "robot_namespace": robot_namespace,
            "initial_pose": {
                "position": {"x": args.x, "y": args.y, "z": args.z},
                "orientation": {"x": qx, "y": qy, "z": qz, "w": qw},
            },
            "reference_frame": args.reference_frame,
        },
    )
    if not response.success:
        msg = f"spawn_model {args.model}: {response.status_message}"
        raise BelvedereError(msg)
    return response
