"""``libgazebo_ros_control.so``: DefaultRobotHWSim over the robot's transmissions, driving
the joints' actuators from the commands its controller_manager's controllers set."""

from __future__ import annotations

import logging
import math

import mujoco

from belvedere.graph import NS
from belvedere.sim.physics._motor import VelocityMotor
from belvedere.sim.physics._plugin import Plugin, PluginContext
from belvedere.sim.physics._ros_control._hardware import JointHandle, Pid
from belvedere.sim.physics._ros_control._manager import ControllerManager
from belvedere.sim.physics._spec import ModelError

__all__ = ["RosControl"]

logger = logging.getLogger("belvedere.ros_control")


INTERFACES = {"EffortJointInterface": "effort", "VelocityJointInterface": "velocity"}
INTERFACES |= {"PositionJointInterface": "position"}


class RosControl(Plugin):
    """``libgazebo_ros_control.so``: the robot's joints with transmissions, as a
    hardware interface, and its controller_manager."""

    NAMESPACE_DEFAULTS_TO_MODEL = True

    def __init__(self, ctx: PluginContext) -> None:
        super().__init__(ctx)
        sim_type = self.text("robotSimType")
        if sim_type and sim_type not in ("gazebo_ros_control/DefaultRobotHWSim", ""):
            logger.warning("%s: robotSimType %r: using DefaultRobotHWSim", ctx.source, sim_type)
        period = self.number("controlPeriod", 0.0)
        self.period_ns = round(period * NS) if period > 0 else 0
        self.last_ns: int | None = None
        self.handles = self._handles()
        ns = self.namespace()
        gains = ctx.graph.params.get(f"{ns.rstrip('/')}/gazebo_ros_control/pid_gains", {}) or {}
        missing = []
        for handle in self.handles.values():
            handle.pid = (
                Pid.from_params(gains.get(handle.name)) if isinstance(gains, dict) else None
            )
            if handle.pid is None and handle.interface != "effort":
                missing.append(handle.name)
        for handle in self.handles.values():
            if handle.interface == "velocity" and handle.pid is None:
                # Gazebo's joint motor: the velocity within the effort limit, as a constraint
                joint = self.robot.joints[handle.name]
                handle.motor = VelocityMotor(
                    self._actuator(handle.name), joint, handle.effort_limit
                )
        if missing:
            logger.warning(
                "ros_control: no PID gains for %s (%s/gazebo_ros_control/pid_gains/<joint>): "
                "velocity joints follow like Gazebo's joint motor, position joints like a stiff "
                "servo, within their effort limits",
                ", ".join(missing),
                ns.rstrip("/"),
            )
        unlimited = [h.name for h in self.handles.values() if not math.isfinite(h.effort_limit)]
        if unlimited:
            logger.warning(
                "ros_control: %s have no effort limit in the URDF: their commands are followed "
                "with any force (add <limit effort=…> for realistic starts and stops)",
                ", ".join(unlimited),
            )
        self.manager = ControllerManager(self, ns, self.handles)

    def _handles(self) -> dict[str, JointHandle]:
        handles: dict[str, JointHandle] = {}
        model = self.robot.model
        for transmission in model.transmissions:
            for tj in transmission.joints:
                interfaces = tj.hardware_interfaces or next(
                    (
                        a.hardware_interfaces
                        for a in transmission.actuators
                        if a.hardware_interfaces
                    ),
                    (),
                )
                kind = None
                for name in interfaces:
                    kind = INTERFACES.get(name.rsplit("/", 1)[-1])
                    if kind:
                        break
                if kind is None:
                    msg = (
                        f"transmission {transmission.name!r}: joint {tj.name!r} needs a "
                        "hardwareInterface (Effort-, Velocity- or PositionJointInterface)"
                    )
                    raise ModelError(msg, transmission.source.best)
                if tj.name not in self.robot.joints:
                    msg = f"transmission {transmission.name!r}: {tj.name!r} is not a movable joint"
                    raise ModelError(msg, transmission.source.best)
                joint = next(j for j in model.joints if j.name == tj.name)
                limit = joint.limit
                bounds = joint.position_range
                handles[tj.name] = JointHandle(
                    tj.name,
                    kind,
                    limit.effort if limit and limit.effort > 0 else math.inf,
                    limit.velocity if limit and limit.velocity > 0 else math.inf,
                    bounds[0] if bounds else None,
                    bounds[1] if bounds else None,
                )
        return handles

    def joint_names(self) -> tuple[str, ...]:
        # Reported once a joint_state_controller runs, which ros_control setups always spawn.
        return tuple(self.handles)

    def wheel_geometry(self, left: str, right: str) -> tuple[float, float]:
        """Wheel separation and radius from the URDF (diff_drive_controller's fallback)."""
        model = self.robot.model
        joints = {j.name: j for j in model.joints}
        if left not in joints or right not in joints:
            msg = f"diff_drive_controller: wheels {left!r}/{right!r} are not joints"
            raise ModelError(msg)
        poses = model.forward_kinematics()
        a, b = poses[joints[left].child], poses[joints[right].child]
        separation = float(((a[:3, 3] - b[:3, 3]) ** 2).sum() ** 0.5)
        collisions = model.link(joints[left].child).collisions
        radius = next((getattr(c.geometry, "radius", 0.0) for c in collisions), 0.0)
        if radius <= 0:
            msg = f"diff_drive_controller: give wheel_radius (wheel {left!r} has no cylinder)"
            raise ModelError(msg)
        return separation, float(radius)

    # --- model -----------------------------------------------------------------------------------
    def prepare(self, spec: mujoco.MjSpec) -> None:
        for handle in self.handles.values():
            if handle.motor is not None:
                handle.motor.add_to(spec)
                continue
            actuator = spec.add_actuator(name=self._actuator(handle.name))
            actuator.target = self.robot.joints[handle.name]
            actuator.trntype = mujoco.mjtTrn.mjTRN_JOINT
            if handle.interface == "position" and handle.pid is None:
                actuator.set_to_position(kp=2000.0, dampratio=1.0)
            else:
                actuator.set_to_motor()
            if math.isfinite(handle.effort_limit):
                actuator.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
                actuator.forcerange = [-handle.effort_limit, handle.effort_limit]

    def _actuator(self, joint: str) -> str:
        return f"{self.robot.name}/ros_control/{joint}"

    def bind(self) -> None:
        for handle in self.handles.values():
            handle.ref = self.engine.joint(self.robot.joints[handle.name])
            handle.actuator = self.engine.actuator_id(self._actuator(handle.name))
            if handle.motor is not None:
                handle.motor.bind(self.engine)
                handle.motor.apply(self.engine)

    def update(self, now_ns: int) -> None:
        for h in self.handles.values():
            if h.motor is not None:
                h.motor.apply(self.engine)
        if self.last_ns is not None and self.period_ns and now_ns - self.last_ns < self.period_ns:
            return
        dt = (now_ns - self.last_ns) / NS if self.last_ns is not None else 0.0
        self.last_ns = now_ns
        d = self.engine.d
        for h in self.handles.values():
            assert h.ref is not None
            h.position = float(d.qpos[h.ref.qpos])
            h.velocity = float(d.qvel[h.ref.dof])
            h.effort = float(d.actuator_force[h.actuator])
        self.manager.update(now_ns, dt)
        for h in self.handles.values():
            if h.motor is not None:
                h.motor.command(self._control(h, dt))
                h.motor.apply(self.engine)
            else:
                d.ctrl[h.actuator] = self._control(h, dt)

    def _control(self, h: JointHandle, dt: float) -> float:
        if h.command is None:
            # nothing commands it: hold still (velocity 0 / current position / no effort)
            if h.interface == "velocity" and h.pid is None:
                return 0.0
            if h.interface == "position" and h.pid is None:
                return h.position
            return 0.0
        command = h.command
        if h.interface == "effort":
            return min(max(command, -h.effort_limit), h.effort_limit)
        if h.interface == "velocity":
            command = min(max(command, -h.velocity_limit), h.velocity_limit)
            if h.pid is None:
                return command
            return h.pid(command - h.velocity, dt)
        if h.lower is not None and h.upper is not None:
            command = min(max(command, h.lower), h.upper)
        if h.pid is None:
            return command
        return h.pid(command - h.position, dt)

    def reset(self) -> None:
        for controller in self.manager.controllers.values():
            if controller.running:
                controller.start()
