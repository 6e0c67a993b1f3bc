"""Wheeled robots written as URDF text from a few numbers, and a trial that drives one in the
physics engine and measures what the acceptance of issue 13 asks: how far the body leaves
the ground, the heading error of a straight run, the steady speeds, a turn's first direction.

Every number comes from the simulation's own state after each physics step (simulated time).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph
from belvedere.sim.physics import PhysicsSimulation


@dataclass(frozen=True)
class Wheeled:
    """A base cylinder, driven wheels (two, or four for a skid-steer) and, for two wheels,
    frictionless caster spheres front and back."""

    wheel_mass: float = 2.0
    wheel_radius: float = 0.06
    base_mass: float = 20.0
    torque: float = 30.0
    """wheelTorque (diff drive) or torque (skid steer), N*m."""
    acceleration: float = 0.0
    """wheelAcceleration (diff drive only), m/s^2; 0: none."""
    plugin: str = "diff"
    """``diff``: gazebo_ros_diff_drive; ``skid``: gazebo_ros_skid_steer_drive (four wheels)."""

    @property
    def width(self) -> float:
        return min(max(0.01, 0.4 * self.wheel_radius), 0.03)

    @property
    def base_radius(self) -> float:
        return max(0.12, 1.5 * self.wheel_radius)

    @property
    def separation(self) -> float:
        return 2 * (self.base_radius + self.width / 2 + 0.01)

    def urdf(self) -> str:
        r, w, rb = self.wheel_radius, self.width, self.base_radius
        hb = r  # the base's half height r/2 leaves r/2 under it
        mw, mb = self.wheel_mass, self.base_mass
        rc = r / 2
        caster_mass = max(0.01, 0.05 * mb)
        parts = [
            '<robot name="wheeled">',
            '<link name="base_footprint"/>',
            '<joint name="base_joint" type="fixed"><parent link="base_footprint"/>'
            f'<child link="base_link"/><origin xyz="0 0 {r}"/></joint>',
            '<link name="base_link">',
            f'<collision><geometry><cylinder radius="{rb}" length="{hb}"/></geometry></collision>',
            _inertial(mb, _cylinder(mb, rb, hb)),
            "</link>",
        ]
        y = rb + w / 2 + 0.01
        wheels: list[tuple[str, float, float]]
        if self.plugin == "skid":
            x = 0.6 * rb
            wheels = [
                ("left_front", x, y),
                ("right_front", x, -y),
                ("left_rear", -x, y),
                ("right_rear", -x, -y),
            ]
        else:
            wheels = [("left", 0.0, y), ("right", 0.0, -y)]
        for name, x, wy in wheels:
            parts += [
                f'<joint name="{name}_wheel_joint" type="continuous"><parent link="base_link"/>'
                f'<child link="{name}_wheel"/><origin xyz="{x} {wy} 0"/><axis xyz="0 1 0"/>'
                "</joint>",
                f'<link name="{name}_wheel"><collision><origin rpy="1.5707963 0 0"/>'
                f'<geometry><cylinder radius="{r}" length="{w}"/></geometry></collision>',
                _inertial(mw, _cylinder(mw, r, w, axis="y")),
                "</link>",
            ]
        if self.plugin != "skid":
            for name, x in (("front", 0.8 * rb - rc), ("back", -(0.8 * rb - rc))):
                parts += [
                    f'<joint name="{name}_caster_joint" type="fixed"><parent link="base_link"/>'
                    f'<child link="{name}_caster"/><origin xyz="{x} 0 {-(r - rc)}"/></joint>',
                    f'<link name="{name}_caster"><collision><geometry><sphere radius="{rc}"/>'
                    "</geometry></collision>",
                    _inertial(caster_mass, (0.4 * caster_mass * rc * rc,) * 3),
                    "</link>",
                ]
        parts.append(self._plugin())
        parts.append("</robot>")
        return "\n".join(parts)

    def _plugin(self) -> str:
        if self.plugin == "skid":
            return (
                '<gazebo><plugin name="skid" filename="libgazebo_ros_skid_steer_drive.so">'
                "<updateRate>100</updateRate><robotNamespace>/</robotNamespace>"
                "<leftFrontJoint>left_front_wheel_joint</leftFrontJoint>"
                "<rightFrontJoint>right_front_wheel_joint</rightFrontJoint>"
                "<leftRearJoint>left_rear_wheel_joint</leftRearJoint>"
                "<rightRearJoint>right_rear_wheel_joint</rightRearJoint>"
                f"<wheelSeparation>{self.separation}</wheelSeparation>"
                f"<wheelDiameter>{2 * self.wheel_radius}</wheelDiameter>"
                f"<torque>{self.torque}</torque>"
                "<robotBaseFrame>base_footprint</robotBaseFrame>"
                "<broadcastTF>true</broadcastTF>"
                "</plugin></gazebo>"
            )
        return (
            '<gazebo><plugin name="drive" filename="libgazebo_ros_diff_drive.so">'
            "<updateRate>100</updateRate><publishTf>1</publishTf><robotNamespace>/</robotNamespace>"
            "<leftJoint>left_wheel_joint</leftJoint><rightJoint>right_wheel_joint</rightJoint>"
            f"<wheelSeparation>{self.separation}</wheelSeparation>"
            f"<wheelDiameter>{2 * self.wheel_radius}</wheelDiameter>"
            f"<wheelTorque>{self.torque}</wheelTorque>"
            f"<wheelAcceleration>{self.acceleration}</wheelAcceleration>"
            "</plugin></gazebo>"
        )


def _cylinder(m: float, r: float, h: float, *, axis: str = "z") -> tuple[float, float, float]:
    across = m * (3 * r * r + h * h) / 12
    along = m * r * r / 2
    return (across, along, across) if axis == "y" else (across, across, along)


def _inertial(m: float, diagonal: tuple[float, ...]) -> str:
    ixx, iyy, izz = diagonal
    return (
        f'<inertial><mass value="{m}"/><inertia ixx="{ixx}" ixy="0" ixz="0" iyy="{iyy}" '
        f'iyz="0" izz="{izz}"/></inertial>'
    )


@dataclass
class Trial:
    """A robot driven from rest: ``start`` s idle, then one command for ``duration`` s."""

    t: list[float] = field(default_factory=list)
    z: list[float] = field(default_factory=list)
    yaw: list[float] = field(default_factory=list)
    speed: list[float] = field(default_factory=list)
    """Forward speed in the body's yaw frame, m/s."""
    turn: list[float] = field(default_factory=list)
    """Yaw rate, rad/s."""
    stopped: str | None = None
    rest_z: float = 0.0

    def after(self, t0: float) -> slice:
        first = next((i for i, t in enumerate(self.t) if t >= t0), len(self.t))
        return slice(first, len(self.t))

    def max_z_excursion(self) -> float:
        return float(np.max(np.abs(np.asarray(self.z) - self.rest_z)))


def drive(
    urdf: str,
    *,
    start: float,
    linear: float,
    angular: float,
    duration: float,
    model: RobotModel | None = None,
    step: float | None = None,
) -> Trial:
    """Spawn the robot (its base footprint on the ground), wait ``start`` s, command
    ``(linear, angular)`` on /cmd_vel and run ``duration`` s more, recording every step."""
    from belvedere.world import empty_world

    world = empty_world()
    if step is not None:
        from dataclasses import replace

        world = replace(world, physics=replace(world.physics, max_step_size=step))
    graph = Graph()
    sim = PhysicsSimulation(graph, world)
    robot = sim.spawn(model or RobotModel.from_string(urdf), name="robot")
    engine = sim.engine
    root = engine.body_id(robot.build.root_body)
    trial = Trial()
    base = robot.model.root_link.name

    def record() -> None:
        pose = engine.link_pose(robot.build, base)
        yaw = math.atan2(float(pose[1, 0]), float(pose[0, 0]))
        vel = engine.body_velocity(root)
        trial.t.append(graph.now_ns() / 1e9)
        trial.z.append(float(pose[2, 3]))
        if trial.yaw:  # unwrapped
            previous = trial.yaw[-1]
            yaw = previous + math.remainder(yaw - previous, 2 * math.pi)
        trial.yaw.append(yaw)
        trial.speed.append(math.cos(yaw) * float(vel[3]) + math.sin(yaw) * float(vel[4]))
        trial.turn.append(float(vel[2]))

    sim.after_step.append(record)
    probe = graph.create_node("probe")
    cmd = probe.publisher("/cmd_vel", "geometry_msgs/Twist", latch=True)
    if start > 0:
        graph.run(duration=start)
    trial.rest_z = trial.z[-1] if trial.z else float(engine.link_pose(robot.build, base)[2, 3])
    cmd.publish_data({"linear": {"x": linear}, "angular": {"z": angular}})
    graph.run(duration=duration)
    trial.stopped = sim.stopped_reason
    return trial


GRAVITY = 9.81


@dataclass(frozen=True)
class Figures:
    """The acceptance figures of one robot: a straight run and a turn in place."""

    z_excursion: float
    """m: how far the base footprint left its resting height, worst of both runs."""
    heading_error: float
    """rad: yaw change 2 s into the straight run."""
    speed_error: float
    """Relative error of the steady forward speed."""
    turn_error: float
    """Relative error of the steady turn rate."""
    wrong_way: float
    """rad: how far the turn went against its command first (0: never)."""
    cap_limits: bool
    """The torque cap (not the command) sets how long speeding up takes."""
    stopped: str | None


def settle_time(robot: Wheeled, speed: float) -> float:
    """Seconds the torque cap (and wheelAcceleration) need to bring the robot to ``speed``."""
    wheels = 4 if robot.plugin == "skid" else 2
    # wheels roll (1.5 m each); the motors carry as much again as armature
    total = 2 * (robot.base_mass + wheels * robot.wheel_mass * 1.5)
    accel = wheels * robot.torque / robot.wheel_radius / total
    if robot.acceleration > 0:
        accel = min(accel, robot.acceleration)
    return speed / accel


def figures(robot: Wheeled, *, start: float, linear: float, angular: float) -> Figures:
    """Drive ``robot`` straight at ``linear`` and, anew, turn it in place at ``angular``."""
    urdf = robot.urdf()
    turn_speed = angular * robot.separation / 2
    ramp = max(settle_time(robot, linear), settle_time(robot, turn_speed))
    duration = max(2.5, 1.5 + 2 * ramp)
    straight = drive(urdf, start=start, linear=linear, angular=0.0, duration=duration)
    turn = drive(urdf, start=start, linear=0.0, angular=angular, duration=duration)
    window = straight.after(start + duration - 0.5)
    begin = straight.after(start).start
    yaw0 = straight.yaw[begin - 1] if begin else 0.0
    at_2s = straight.after(start + 2.0).start
    heading = abs(straight.yaw[min(at_2s, len(straight.yaw) - 1)] - yaw0)
    speed = float(np.mean(straight.speed[window]))
    t_window = turn.after(start + duration - 0.5)
    t_begin = turn.after(start).start
    t_yaw0 = turn.yaw[t_begin - 1] if t_begin else 0.0
    rate = float(np.mean(turn.turn[t_window]))
    swept = (np.asarray(turn.yaw[t_begin:]) - t_yaw0) * math.copysign(1.0, angular)
    return Figures(
        z_excursion=max(straight.max_z_excursion(), turn.max_z_excursion()),
        heading_error=heading,
        speed_error=abs(speed - linear) / abs(linear),
        turn_error=abs(rate - angular) / abs(angular),
        wrong_way=max(0.0, -float(np.min(swept))),
        cap_limits=ramp > 0.5,
        stopped=straight.stopped or turn.stopped,
    )
