"""rotate_recovery's turn, driven cycle by cycle in simulated time."""

from __future__ import annotations

import math

import numpy as np
import pytest

from belvedere.nav.recovery import (
    RotateOutcome,
    RotateRecovery,
    RotateRecoveryParams,
    first_collision,
)
from tests.nav.local_world import SQUARE, inflate, walled


def test_turns_once_around_in_open_space() -> None:
    grid = inflate(walled(3.0, 3.0))
    params = RotateRecoveryParams.from_mapping({"frequency": 10.0}, {"acc_lim_th": 1.2})
    start = 0.3
    recovery = RotateRecovery(params, start)
    yaw, turned, speeds = start, 0.0, []
    for _ in range(500):
        decision = recovery.step(grid, (1.5, 1.5, math.remainder(yaw, math.tau)), SQUARE)
        if decision.outcome is RotateOutcome.DONE:
            break
        assert decision.outcome is RotateOutcome.ROTATING
        speeds.append(decision.vth)
        yaw += decision.vth * params.period
        turned += decision.vth * params.period
    else:
        pytest.fail("the turn never ended")
    assert turned == pytest.approx(2 * math.pi, abs=params.tolerance + 0.1)
    assert min(speeds) >= params.min_rotational_vel
    assert max(speeds) <= params.max_rotational_vel
    # full speed, then slowing down towards the end as sqrt(2·acc·left)
    assert speeds[0] == pytest.approx(params.max_rotational_vel)
    tail = speeds[-5:]
    assert tail == sorted(tail, reverse=True)
    assert speeds[-1] < 0.8


def test_a_wall_within_the_sweep_blocks_the_turn() -> None:
    lethal = walled(3.0, 3.0)
    lethal[:, 34] = True  # x = 1.70 m: the square's front edge is at 1.65, its corners reach 1.71
    grid = inflate(lethal)
    pose = (1.5, 1.5, 0.0)
    hit = first_collision(grid, pose, SQUARE, 2 * math.pi, 0.017)
    assert hit is not None
    assert 0.0 < hit < math.pi / 4
    decision = RotateRecovery(RotateRecoveryParams(), 0.0).step(grid, pose, SQUARE)
    assert decision.outcome is RotateOutcome.BLOCKED
    assert decision.blocked_at == pytest.approx(hit)
    assert decision.vth == 0.0
    # a round robot of the inscribed radius turns there freely
    assert first_collision(grid, pose, np.zeros((0, 2)), 2 * math.pi, 0.017) is None


def test_free_sweeps_and_granularity() -> None:
    grid = inflate(walled(3.0, 3.0))
    assert first_collision(grid, (1.5, 1.5, 0.0), SQUARE, 2 * math.pi, 0.017) is None
    assert first_collision(grid, (1.5, 1.5, 0.0), SQUARE, 0.0, 0.017) is None


def test_parameters_come_from_the_trajectory_planner_namespace() -> None:
    params = RotateRecoveryParams.from_mapping(
        {"sim_granularity": 0.05},
        {"acc_lim_th": 1.2, "max_rotational_vel": 0.8, "min_in_place_vel_theta": 0.5},
    )
    assert params.sim_granularity == 0.05
    assert (params.acc_lim_th, params.max_rotational_vel, params.min_rotational_vel) == (
        1.2,
        0.8,
        0.5,
    )
    assert params.tolerance == 0.10
    assert params.period == pytest.approx(0.05)
    newer = RotateRecoveryParams.from_mapping(
        {}, {"acc_lim_theta": 2.0, "acc_lim_th": 1.0, "max_vel_theta": 0.6}
    )
    assert (newer.acc_lim_th, newer.max_rotational_vel) == (2.0, 0.6)
    with pytest.raises(ValueError, match=r"parameter frequency must be positive, got 0"):
        RotateRecoveryParams.from_mapping({"frequency": 0})
