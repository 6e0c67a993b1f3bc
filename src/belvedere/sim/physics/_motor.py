"""A joint held at a commanded velocity by a force no larger than a cap: Gazebo's joint motor
(``joint->SetParam("fmax", torque)`` and ``SetParam("vel", speed)``, a velocity constraint ODE
solves with the contacts).

In MuJoCo it is a velocity actuator, ``force = kv * (target - velocity)``, whose damping the
implicit integrators (``implicitfast``, our default) fold into the step: the velocity the
force acts on is the one at the *end* of the step, so a stiff ``kv`` cannot overshoot the way
an explicit servo does on a light wheel. Two things keep it that way:

* ``kv`` is matched to the joint's own inertia and the step (``STIFFNESS * M_jj / dt``): a
  free wheel closes most of its velocity error in one step, one on the ground (carrying its
  share of the robot) a little more slowly, but in a few steps.
* The cap is met by lowering ``kv`` each step to ``cap / |error|`` when the error is large,
  never by clamping the force: a clamped force is applied explicitly (MuJoCo drops its
  derivative), and a 30 N*m cap on a 0.1 kg wheel then swings it by hundreds of rad/s per
  step. With the lowered gain the force starts at the cap and fades as the wheel arrives.
  ``forcerange`` still holds the cap, as a safety net.
"""

from __future__ import annotations

import logging
import math
from typing import Any

import mujoco

from belvedere.description.urdf import RobotModel
from belvedere.sim._commands import CommandGate
from belvedere.sim.physics._engine import Engine
from belvedere.sim.physics._plugin import Plugin, PluginContext, RateGate

__all__ = ["STIFFNESS", "MotorDrive", "VelocityMotor", "wheel_load"]

logger = logging.getLogger("belvedere.physics")

STIFFNESS = 1.0
"""``kv`` as a multiple of the joint's inertia per step (dimensionless)."""
ARMATURE_SHARE = 1.0
"""The share of a wheel's carried inertia given to it as armature."""
INTEGRAL_TIME = 0.05
"""s: how fast the motor learns a steady load (the velocity error it leaves, integrated), so
the joint holds its command as Gazebo's constraint does rather than a damper's droop."""


class VelocityMotor:
    """One velocity-controlled joint: ``add_to`` a spec before compiling, ``bind`` after each
    compile, ``command`` a target at any time, ``apply`` before the next physics step — before
    every step while :attr:`capped`, otherwise whenever the command changes or at the
    plugin's own rate (the gain is then constant and the load correction slow)."""

    def __init__(self, actuator: str, joint: str, max_force: float) -> None:
        """``joint``: the MuJoCo joint name; ``max_force``: N*m (or N), ``inf`` for none."""
        self.actuator = actuator
        self.joint = joint
        self.max_force = max_force
        self.target = 0.0
        self.offset = 0.0
        """What the target is raised by to hold it against a steady load (rad/s)."""
        self.id = -1
        self.dof = -1
        self.kv_max = 0.0
        self.capped = False
        """The last :meth:`apply` met the cap (the gain must follow the error every step)."""

    def add_to(self, spec: mujoco.MjSpec, *, carried: float = 0.0) -> None:
        """``carried``: inertia the joint moves beyond its own, kg*m^2 (a wheel: its share of
        the robot's mass times its radius squared). A share of it becomes the joint's
        armature (a motor's reflected rotor inertia), so the contact solver, which does not
        see the actuator's implicit damping, sees a joint about as stiff as the motor."""
        joint = spec.joint(self.joint)
        joint.armature = max(float(joint.armature), ARMATURE_SHARE * carried)
        actuator = spec.add_actuator(name=self.actuator)
        actuator.target = self.joint
        actuator.trntype = mujoco.mjtTrn.mjTRN_JOINT
        actuator.set_to_velocity(kv=1.0)  # the gain is set by apply()
        if math.isfinite(self.max_force):
            actuator.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
            # a little above the cap: apply() keeps the force within it, and a force exactly
            # at the range would count as clamped (and lose its implicit treatment)
            cap = self.max_force * (1.0 + 1e-6)
            actuator.forcerange = [-cap, cap]

    def bind(self, engine: Engine) -> None:
        m, d = engine.m, engine.d
        self.id = engine.actuator_id(self.actuator)
        self.dof = engine.joint(self.joint).dof
        self.kv_max = STIFFNESS * float(m.dof_M0[self.dof]) / float(m.opt.timestep)
        self.timestep = float(m.opt.timestep)
        # Views into MjModel/MjData, valid until the next compile (bind runs after each):
        # each attribute read otherwise makes a new view, at 100 Hz per motor.
        self._gain = m.actuator_gainprm[self.id]
        self._bias = m.actuator_biasprm[self.id]
        self._ctrl = d.ctrl
        self._qvel = d.qvel

    def command(self, velocity: float) -> None:
        if velocity != self.target:
            self.offset = 0.0  # a new command starts without the old load's correction
        self.target = velocity

    def apply(self, engine: Engine, elapsed: float | None = None) -> None:
        """Set the gain and the target for the next step; ``elapsed``: seconds since the last
        apply (one step if not given)."""
        signed = self.target - float(self._qvel[self.dof])
        error = abs(signed)
        kv = self.kv_max
        self.capped = error * kv > self.max_force
        if self.capped:
            kv = self.max_force / error
        else:  # within the cap: integrate what a steady load leaves (none while capped)
            dt = self.timestep if elapsed is None else elapsed
            self.offset += signed * dt / INTEGRAL_TIME
        self._gain[0] = kv
        self._bias[2] = -kv
        self._ctrl[self.id] = self.target + self.offset


def wheel_load(model: RobotModel, wheels: int, radius: float) -> float:
    """The inertia one of ``wheels`` driven wheels of ``radius`` moves with the robot: its
    share of the robot's mass, at the rim (kg*m^2)."""
    mass = sum(link.inertial.mass for link in model.links if link.inertial is not None)
    return max(mass, 0.0) / max(wheels, 1) * radius * radius


class MotorDrive(Plugin):
    """What the wheel-driving plugins (diff drive, skid steer) share: a Twist command checked
    by the command gate, velocity motors on the wheels (added before compiling, bound after),
    re-applied when the plugin acts at its rate or, while one is capped, every step."""

    diameter: float
    """The wheels' diameter (m), read by the plugin."""
    gate: RateGate
    """The plugin's update rate, set by the plugin."""

    def __init__(self, ctx: PluginContext) -> None:
        super().__init__(ctx)
        self.motors: list[VelocityMotor] = []
        self.commands = CommandGate(ctx.name, ctx.graph, logger)
        self.x = self.rot = 0.0
        self.applied_ns = ctx.graph.now_ns()
        self.capped = False
        """Whether a motor met its cap at its last apply (read twice a batch)."""

    def _on_cmd(self, msg: Any) -> None:
        x, rot = float(msg.linear.x), float(msg.angular.z)
        if not self.commands.accept(linear={"linear.x": x}, angular={"angular.z": rot}):
            return
        self.x, self.rot = x, rot

    def prepare(self, spec: mujoco.MjSpec) -> None:
        carried = wheel_load(self.robot.model, len(self.motors), self.diameter / 2)
        for motor in self.motors:
            motor.add_to(spec, carried=carried)

    def bind_motors(self) -> None:
        for motor in self.motors:
            motor.bind(self.engine)
            motor.apply(self.engine)
        self.capped = any(m.capped for m in self.motors)

    def stop_motors(self) -> None:
        """After a world reset: no command, the gate and the motors started over."""
        self.x = self.rot = 0.0
        for motor in self.motors:
            motor.command(0.0)
        now = self.ctx.graph.now_ns()
        self.gate.reset(now)
        self.apply_motors(now, due=True)

    def next_update_ns(self, now_ns: int) -> int | None:
        return None if self.capped else self.gate.next_ns()

    def apply_motors(self, now_ns: int, *, due: bool) -> None:
        """The motors after a step: applied when the plugin acted (``due``) or while one is
        capped, with the time since they were last applied."""
        if not due and not self.capped:
            return
        elapsed = max(now_ns - self.applied_ns, 0) / 1e9 or None
        capped = False
        for motor in self.motors:
            motor.apply(self.engine, elapsed)
            capped = capped or motor.capped
        self.applied_ns = now_ns
        self.capped = capped
