"""The vectorised rollouts against the trajectory generators' loops, restated point by point."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from belvedere.nav.local._rollout import rollout, velocity_samples

Floats = npt.NDArray[np.float64]


def approach(target: float, current: float, acc: float, dt: float) -> float:
    if target >= current:
        return min(target, current + acc * dt)
    return max(target, current - acc * dt)


Triple = tuple[float, float, float]


def trajectory_planner_loop(
    pose: Triple, vel: Triple, sample: Floats, steps: int, sim_time: float, acc: Triple
) -> Floats:
    """base_local_planner's generateTrajectory: add the point, then accelerate, then move."""
    x, y, th = pose
    vx, vy, vth = vel
    dt = sim_time / steps
    points: list[Triple] = []
    for _ in range(steps):
        points.append((x, y, th))
        vx = approach(sample[0], vx, acc[0], dt)
        vy = approach(sample[1], vy, acc[1], dt)
        vth = approach(sample[2], vth, acc[2], dt)
        x += (vx * math.cos(th) + vy * math.cos(math.pi / 2 + th)) * dt
        y += (vx * math.sin(th) + vy * math.sin(math.pi / 2 + th)) * dt
        th += vth * dt
    return np.array(points)


def dwa_loop(
    pose: Triple,
    vel: Triple,
    sample: Floats,
    steps: int,
    sim_time: float,
    acc: Triple,
    continued: bool,
) -> Floats:
    """SimpleTrajectoryGenerator: with continued acceleration the stored velocity is one
    step on, and each step accelerates once more before moving."""
    x, y, th = pose
    dt = sim_time / steps
    loop = [float(v) for v in sample]
    if continued:
        loop = [approach(sample[a], vel[a], acc[a], dt) for a in range(3)]
    points: list[Triple] = []
    for _ in range(steps):
        points.append((x, y, th))
        if continued:
            loop = [approach(sample[a], loop[a], acc[a], dt) for a in range(3)]
        x += (loop[0] * math.cos(th) + loop[1] * math.cos(math.pi / 2 + th)) * dt
        y += (loop[0] * math.sin(th) + loop[1] * math.sin(math.pi / 2 + th)) * dt
        th += loop[2] * dt
    return np.array(points)


SAMPLES = np.array([[0.5, 0.0, 0.0], [0.3, 0.1, -0.8], [0.0, 0.0, 1.0], [-0.1, -0.3, 0.4]])
STEPS = np.array([20, 13, 40, 7])
POSE = (1.0, 2.0, 0.7)
VELOCITY = (0.2, 0.05, -0.3)
ACC = (2.5, 2.5, 3.2)


def test_trajectory_planner_rollouts() -> None:
    r = rollout(POSE, VELOCITY, SAMPLES, STEPS, 1.0, ACC, accelerate=True, first_increment=1)
    for s in range(len(SAMPLES)):
        expected = trajectory_planner_loop(POSE, VELOCITY, SAMPLES[s], int(STEPS[s]), 1.0, ACC)
        assert np.allclose(r.points(s), expected, atol=1e-12)
        assert r.dt[s] == pytest.approx(1.0 / STEPS[s])


@pytest.mark.parametrize("continued", [True, False])
def test_dwa_rollouts(continued: bool) -> None:
    r = rollout(POSE, VELOCITY, SAMPLES, STEPS, 1.7, ACC, accelerate=continued, first_increment=2)
    for s in range(len(SAMPLES)):
        expected = dwa_loop(POSE, VELOCITY, SAMPLES[s], int(STEPS[s]), 1.7, ACC, continued)
        assert np.allclose(r.points(s), expected, atol=1e-12)


def test_velocity_samples_as_dwas_iterator() -> None:
    assert velocity_samples(0.2, 0.2, 5).tolist() == [0.2]
    assert velocity_samples(0.0, 0.5, 3).tolist() == [0.0, 0.25, 0.5]
    assert velocity_samples(0.0, 0.5, 1).tolist() == [0.0, 0.5]  # at least two
    # zero joins a range that crosses it
    assert velocity_samples(-0.3, 0.3, 4).tolist() == pytest.approx([-0.3, -0.1, 0.0, 0.1, 0.3])
    assert velocity_samples(-0.2, 0.2, 3).tolist() == [-0.2, 0.0, 0.2]
