"""The MuJoCo model and data of one simulation, and what plugins ask of them: poses and
velocities of links, joint positions and velocities, actuators, rays, and a health check.

The spec stays editable: robots are added (spawned) at any time and the model recompiled
with MuJoCo keeping the state of everything already there.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import mujoco
import numpy as np
import numpy.typing as npt

from belvedere.sim.physics._builder import RobotBuild, new_spec
from belvedere.world import Physics

__all__ = ["DivergenceError", "Engine", "JointRef"]

Matrix4 = npt.NDArray[np.float64]


class DivergenceError(Exception):
    """The simulation produced NaN or exploded."""


@dataclass
class JointRef:
    """Where a joint's numbers live in MjData (valid until the next recompile)."""

    id: int
    qpos: int
    dof: int


class Engine:
    """MjSpec → MjModel/MjData, with name-based access for plugins."""

    def __init__(self, physics: Physics) -> None:
        self.physics = physics
        self.spec = new_spec(physics)
        self.model: mujoco.MjModel | None = None
        self.data: mujoco.MjData | None = None
        self.on_recompile: list[Callable[[], None]] = []

    # --- compiling -------------------------------------------------------------------------------
    def compile(self) -> None:
        if self.model is None or self.data is None:
            self.model = self.spec.compile()
            self.data = mujoco.MjData(self.model)
        else:
            self.model, self.data = self.spec.recompile(self.model, self.data)
        mujoco.mj_forward(self.model, self.data)
        for hook in self.on_recompile:
            hook()

    @property
    def m(self) -> mujoco.MjModel:
        assert self.model is not None, "compile() first"
        return self.model

    @property
    def d(self) -> mujoco.MjData:
        assert self.data is not None, "compile() first"
        return self.data

    # --- lookups ---------------------------------------------------------------------------------
    def body_id(self, name: str) -> int:
        if name == "world":
            return 0
        return int(mujoco.mj_name2id(self.m, mujoco.mjtObj.mjOBJ_BODY, name))

    def joint(self, name: str) -> JointRef:
        jid = int(mujoco.mj_name2id(self.m, mujoco.mjtObj.mjOBJ_JOINT, name))
        if jid < 0:
            msg = f"no joint {name!r} in the simulation"
            raise KeyError(msg)
        return JointRef(jid, int(self.m.jnt_qposadr[jid]), int(self.m.jnt_dofadr[jid]))

    def actuator_id(self, name: str) -> int:
        return int(mujoco.mj_name2id(self.m, mujoco.mjtObj.mjOBJ_ACTUATOR, name))

    # --- state -----------------------------------------------------------------------------------
    def body_pose(self, body_id: int) -> Matrix4:
        t = np.eye(4)
        t[:3, :3] = self.d.xmat[body_id].reshape(3, 3)
        t[:3, 3] = self.d.xpos[body_id]
        return t

    def link_pose(self, build: RobotBuild, link: str) -> Matrix4:
        """A URDF link's world pose (its body's pose and the link's offset in it)."""
        body, offset = build.link_body[link]
        result: Matrix4 = self.body_pose(self.body_id(body)) @ offset
        return result

    def body_velocity(self, body_id: int, *, local: bool = False) -> npt.NDArray[np.float64]:
        """(angular xyz, linear xyz) at the body's origin, world (or body) axes. (XBODY: the
        body's own frame; BODY would be its principal-inertia frame.)"""
        res = np.zeros(6)
        mujoco.mj_objectVelocity(
            self.m, self.d, mujoco.mjtObj.mjOBJ_XBODY, body_id, res, 1 if local else 0
        )
        return res

    def body_acceleration(self, body_id: int) -> npt.NDArray[np.float64]:
        """(angular, linear) proper acceleration in body axes (what an IMU measures)."""
        mujoco.mj_rnePostConstraint(self.m, self.d)
        res = np.zeros(6)
        mujoco.mj_objectAcceleration(self.m, self.d, mujoco.mjtObj.mjOBJ_XBODY, body_id, res, 1)
        return res

    def healthy(self) -> str | None:
        """None, or why the state is broken (NaN, or absurd speeds)."""
        d = self.d
        if not (np.all(np.isfinite(d.qpos)) and np.all(np.isfinite(d.qvel))):
            return "the state became NaN"
        if d.qvel.size and float(np.max(np.abs(d.qvel))) > 1e4:
            dof = int(np.argmax(np.abs(d.qvel)))
            body = self.m.body(int(self.m.dof_bodyid[dof])).name
            return f"body {body!r} reached {float(np.max(np.abs(d.qvel))):.3g} (m or rad)/s"
        return None

    def reset(self) -> None:
        """Everything back to where it was built (Gazebo's reset_world)."""
        mujoco.mj_resetData(self.m, self.d)
        mujoco.mj_forward(self.m, self.d)

    def set_free_pose(self, joint: str, pose: Matrix4) -> None:
        ref = self.joint(joint)
        q = np.zeros(4)
        mujoco.mju_mat2Quat(q, np.ascontiguousarray(pose[:3, :3]).reshape(9))
        self.d.qpos[ref.qpos : ref.qpos + 3] = pose[:3, 3]
        self.d.qpos[ref.qpos + 3 : ref.qpos + 7] = q
        self.d.qvel[ref.dof : ref.dof + 6] = 0.0
        mujoco.mj_forward(self.m, self.d)


def yaw_of(m: Matrix4) -> float:
    return math.atan2(float(m[1, 0]), float(m[0, 0]))


def quat_xyzw(m: Matrix4) -> tuple[float, float, float, float]:
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(m[:3, :3]).reshape(9))
    return (float(q[1]), float(q[2]), float(q[3]), float(q[0]))
