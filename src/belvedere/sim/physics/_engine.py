"""The MuJoCo model and data of one simulation, and what plugins ask of them: poses and
velocities of links, joint positions and velocities, actuators, rays, and a health check.

The spec stays editable: robots are added (spawned) at any time and the model recompiled
with MuJoCo keeping the state of everything already there.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Final

import mujoco
import numpy as np
import numpy.typing as npt

from belvedere.sim.physics._builder import RobotBuild
from belvedere.sim.physics._spec import new_spec
from belvedere.world import Physics

__all__ = ["DivergenceError", "Engine", "JointRef", "MujocoWarning"]

Matrix4 = npt.NDArray[np.float64]

logger = logging.getLogger("belvedere.physics")

_W = mujoco.mjtWarning
_BROKEN: Final = {
    int(_W.mjWARN_BADQPOS): "position",
    int(_W.mjWARN_BADQVEL): "velocity",
    int(_W.mjWARN_BADQACC): "acceleration",
}
"""MuJoCo's warnings that it gave up on the state (and reset it to the start, mid-run)."""
_LIMITS: Final = {
    int(_W.mjWARN_INERTIA): "a body's inertia is too small for the solver",
    int(_W.mjWARN_CONTACTFULL): "the contact buffer is full: contacts were dropped",
    int(_W.mjWARN_CNSTRFULL): "the constraint buffer is full: constraints were dropped",
    int(_W.mjWARN_BADCTRL): "a control input was NaN or huge: MuJoCo zeroed the controls",
}


def _mujoco_says(text: str) -> None:
    logger.debug("MuJoCo: %s", text)


# MuJoCo's default prints its warnings to stdout (into ``--echo`` output) and appends them to
# MUJOCO_LOG.TXT in the current directory. They are counted in MjData too, which is where we
# read them (MujocoWarning); unless the application installed a handler of its own.
if mujoco.get_mju_user_warning() is None:
    mujoco.set_mju_user_warning(_mujoco_says)


@dataclass(frozen=True)
class MujocoWarning:
    """A warning MuJoCo counted during the last steps."""

    kind: int
    """An ``mjtWarning`` value."""
    count: int
    text: str
    broken: bool
    """True when MuJoCo found the state unusable and reset it."""


_LAST_ROW = np.array([0.0, 0.0, 0.0, 1.0])
_XBODY: Final = mujoco.mjtObj.mjOBJ_XBODY


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
        self._body_ids: dict[str, int] = {}
        self._warning_counts: npt.NDArray[np.int32] = np.zeros(0, np.int32)
        self._xpos: npt.NDArray[np.float64] = np.zeros((0, 3))
        self._xquat: npt.NDArray[np.float64] = np.zeros((0, 4))

    # --- compiling -------------------------------------------------------------------------------
    def compile(self) -> None:
        self._body_ids.clear()
        if self.model is None or self.data is None:
            self.model = self.spec.compile()
            self.data = mujoco.MjData(self.model)
        else:
            self.model, self.data = self.spec.recompile(self.model, self.data)
        mujoco.mj_forward(self.model, self.data)
        self._warning_counts = self.data.warning.number  # a view into MjData
        # Views kept for what plugins read at their rates (each attribute read of MjData
        # makes a new array object).
        self._xpos, self._xquat = self.data.xpos, self.data.xquat
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
        found = self._body_ids.get(name)
        if found is None:
            found = self._body_ids[name] = int(
                mujoco.mj_name2id(self.m, mujoco.mjtObj.mjOBJ_BODY, name)
            )
        return found

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
        d = self.d
        t = np.empty((4, 4))
        t[:3, :3] = d.xmat[body_id].reshape(3, 3)
        t[:3, 3] = d.xpos[body_id]
        t[3] = _LAST_ROW
        return t

    def link_pose(self, build: RobotBuild, link: str) -> Matrix4:
        """A URDF link's world pose (its body's pose and the link's offset in it)."""
        body, offset = build.link_body[link]
        result: Matrix4 = self.body_pose(self.body_id(body)) @ offset
        return result

    def frame_of(self, build: RobotBuild, link: str) -> tuple[int, Matrix4 | None]:
        """A URDF link's body id and its offset in it (None when the link is the body's
        origin, the common case): for :meth:`position_quat`."""
        body, offset = build.link_body[link]
        return self.body_id(body), None if np.array_equal(offset, np.eye(4)) else offset

    def position_quat(
        self, body_id: int, offset: Matrix4 | None
    ) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
        """A frame's world position and orientation (quaternion xyzw), read straight from
        MuJoCo's body state when the frame is the body's origin."""
        if offset is None:
            x, y, z = self._xpos[body_id].tolist()
            w, qx, qy, qz = self._xquat[body_id].tolist()
            return (x, y, z), (qx, qy, qz, w)
        pose = self.body_pose(body_id) @ offset
        px, py, pz = pose[:3, 3].tolist()
        return (px, py, pz), quat_xyzw(pose)

    def body_velocity(
        self, body_id: int, *, local: bool = False, out: npt.NDArray[np.float64] | None = None
    ) -> npt.NDArray[np.float64]:
        """(angular xyz, linear xyz) at the body's origin, world (or body) axes. (XBODY: the
        body's own frame; BODY would be its principal-inertia frame.) ``out``: six floats to
        fill, for callers that read it at a plugin's rate and keep nothing."""
        res = np.zeros(6) if out is None else out
        mujoco.mj_objectVelocity(self.m, self.d, _XBODY, body_id, res, 1 if local else 0)
        return res

    def body_acceleration(self, body_id: int) -> npt.NDArray[np.float64]:
        """(angular, linear) proper acceleration in body axes (what an IMU measures)."""
        mujoco.mj_rnePostConstraint(self.m, self.d)
        res = np.zeros(6)
        mujoco.mj_objectAcceleration(self.m, self.d, _XBODY, body_id, res, 1)
        return res

    def healthy(self) -> str | None:
        """None, or why the state is broken (NaN, or absurd speeds)."""
        d = self.d
        # The common case in two dot products: a sum of squares is not finite when a value
        # is not (or when huge ones overflow it: then the exact tests below decide), NaN
        # fails <=, and no speed is above 1e4 when their squares' sum is not above 1e8.
        qpos, qvel = d.qpos, d.qvel
        if math.isfinite(float(qpos @ qpos)) and float(qvel @ qvel) <= 1e8:
            return None
        if not (np.all(np.isfinite(d.qpos)) and np.all(np.isfinite(d.qvel))):
            return "the state became NaN"
        if d.qvel.size and float(np.max(np.abs(d.qvel))) > 1e4:
            dof = int(np.argmax(np.abs(d.qvel)))
            body = self.m.body(int(self.m.dof_bodyid[dof])).name
            return f"body {body!r} reached {float(np.max(np.abs(d.qvel))):.3g} (m or rad)/s"
        return None

    def take_warnings(self) -> list[MujocoWarning]:
        """The warnings MuJoCo counted since the last call (cheap when there are none)."""
        counts = self._warning_counts
        if not np.count_nonzero(counts):  # (the cheapest test on numpy's small arrays)
            return []
        out = []
        for kind in np.flatnonzero(counts):
            stat = self.d.warning[int(kind)]
            what = _BROKEN.get(int(kind))
            if what is not None:
                text = (
                    f"MuJoCo found a NaN, infinite or huge {what} of body "
                    f"{self._body_of(int(kind), int(stat.lastinfo))!r} and reset the world "
                    "to its start"
                )
            else:
                text = _LIMITS.get(int(kind), f"MuJoCo warning {int(kind)}")
            out.append(MujocoWarning(int(kind), int(stat.number), text, what is not None))
            stat.number = 0
        return out

    def _body_of(self, kind: int, index: int) -> str:
        """The body whose position (qpos index) or velocity/acceleration (DOF) was bad."""
        m = self.m
        if kind == int(_W.mjWARN_BADQPOS):
            joint = int(np.searchsorted(m.jnt_qposadr, index, side="right")) - 1
            body = int(m.jnt_bodyid[max(joint, 0)]) if m.njnt else 0
        else:
            body = int(m.dof_bodyid[index]) if 0 <= index < m.nv else 0
        return str(m.body(body).name)

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


def planar_twist(
    velocity: npt.NDArray[np.float64], yaw: float
) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """(linear, angular) of an odometry twist from :meth:`Engine.body_velocity` in world axes:
    the ground velocity turned into the heading's frame, so roll and pitch do not leak in as
    they would with the body's own axes."""
    _, _, wz, vx, vy, _ = velocity.tolist()
    c, s = math.cos(yaw), math.sin(yaw)
    return (c * vx + s * vy, c * vy - s * vx, 0.0), (0.0, 0.0, wz)


def quat_xyzw(m: Matrix4) -> tuple[float, float, float, float]:
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(m[:3, :3]).reshape(9))
    return (float(q[1]), float(q[2]), float(q[3]), float(q[0]))
