"""turtlesim's world: the motion, the walls, the pens, the canvas and the names, each checked
against what turtlesim's update does, computed here step by step."""

from __future__ import annotations

import math

import numpy as np
import pytest

from belvedere.sim.turtlesim import (
    BACKGROUND,
    PEN,
    PERIOD,
    SIZE,
    TurtleError,
    TurtleWorld,
)


def _started() -> TurtleWorld:
    world = TurtleWorld()
    world.spawn("", SIZE / 2, SIZE / 2, 0.0)
    assert world.update(0.0) == []  # the first update only notes the time
    return world


def test_the_world_is_11_0889_m_and_turtle1_starts_in_its_centre() -> None:
    assert pytest.approx(11.088888, abs=1e-6) == SIZE
    world = _started()
    (pose,) = world.update(PERIOD)
    assert (pose.name, pose.x, pose.y, pose.theta) == ("turtle1", SIZE / 2, SIZE / 2, 0.0)
    assert pose.color == BACKGROUND


def test_orientation_then_position_for_a_circle() -> None:
    world = _started()
    v, w = 2.0, 1.8
    world.command("turtle1", v, 0.0, w, 0.0)
    x, y, theta = SIZE / 2, SIZE / 2, 0.0
    for step in range(1, 60):
        (pose,) = world.update(step * PERIOD)
        theta += w * PERIOD  # turtlesim turns first, then moves along the new heading
        x += math.cos(theta) * v * PERIOD
        y += math.sin(theta) * v * PERIOD
        assert (pose.x, pose.y, pose.theta) == pytest.approx((x, y, theta), abs=1e-12)
        assert (pose.linear_velocity, pose.angular_velocity) == (v, w)


def test_a_command_lasts_one_second() -> None:
    world = _started()
    world.command("turtle1", 1.0, 0.0, 0.0, 0.0)
    moving = [p.linear_velocity for p in (world.update(k * PERIOD)[0] for k in range(1, 70))]
    assert moving[: math.floor(1.0 / PERIOD)] == [1.0] * 62
    assert moving[63:] == [0.0] * len(moving[63:])


def test_theta_wraps_to_minus_pi_pi() -> None:
    world = _started()
    world.command("turtle1", 0.0, 0.0, 5.0, 0.0)
    thetas = [world.update(k * PERIOD)[0].theta for k in range(1, 62)]
    assert all(-math.pi <= t < math.pi for t in thetas)
    assert min(thetas) < -2.5


def test_the_wall_clamps_and_warns_in_turtlesims_words() -> None:
    world = _started()
    world.command("turtle1", 10.0, 0.0, 0.0, 0.0)
    for k in range(1, 60):
        (pose,) = world.update(k * PERIOD)
        if world.warnings:
            break
    assert pose.x == SIZE
    (warning,) = world.warnings
    assert warning.startswith("Oh no! I hit the wall! (Clamping from [x=11.")
    assert warning.endswith(f", y={SIZE / 2:f}])")


def test_trails_take_the_pen_and_the_colour_sensor_sees_them() -> None:
    world = _started()
    world.command("turtle1", 1.0, 0.0, 0.0, 0.0)
    world.update(PERIOD)
    row = round(SIZE / 2 * 45)
    assert tuple(world.canvas[row, 250]) == PEN
    assert tuple(world.canvas[row + 1, 250]) == PEN  # 3 pixels wide
    assert tuple(world.canvas[row + 3, 250]) == BACKGROUND
    world.set_pen("turtle1", (255, 0, 0), 8, False)
    world.update(2 * PERIOD)
    assert tuple(world.canvas[row + 3, 252]) == (255, 0, 0)
    world.set_pen("turtle1", (0, 255, 0), 1, True)  # off: the pen lifts, its colour stays
    before = world.canvas.copy()
    world.update(3 * PERIOD)
    assert np.array_equal(before, world.canvas)
    world.teleport_absolute("turtle1", SIZE / 2, SIZE / 2, math.pi)  # back over the trail
    (pose,) = world.update(4 * PERIOD)
    assert pose.color == (255, 0, 0)


def test_clear_and_reset() -> None:
    world = _started()
    world.command("turtle1", 1.0, 0.0, 0.0, 0.0)
    world.update(PERIOD)
    world.clear((10, 20, 30))
    assert (world.canvas == (10, 20, 30)).all()
    world.spawn("", 1.0, 1.0, 0.0)
    assert world.reset(BACKGROUND) == "turtle1"
    assert list(world.turtles) == ["turtle1"]
    assert (world.canvas == BACKGROUND).all()


def test_spawn_names_kill_and_teleports() -> None:
    world = _started()
    assert world.spawn("", 1.0, 2.0, 0.5) == "turtle2"
    assert world.spawn("leo", 3.0, 4.0, 0.0) == "leo"
    with pytest.raises(TurtleError, match=r"A turtled named \[leo\] already exists"):
        world.spawn("leo", 1.0, 1.0, 0.0)
    with pytest.raises(TurtleError, match="not a number"):
        world.spawn("nan", math.nan, 1.0, 0.0)
    world.kill("turtle2")
    with pytest.raises(TurtleError, match=r"Tried to kill turtle \[turtle2\]"):
        world.kill("turtle2")
    assert world.spawn("", 1.0, 1.0, 0.0) == "turtle3"  # the count goes on
    world.teleport_relative("leo", 1.0, math.pi / 2)
    poses = {p.name: p for p in world.update(PERIOD)}
    assert (poses["leo"].x, poses["leo"].y) == pytest.approx((3.0, 5.0))
    assert poses["leo"].theta == pytest.approx(math.pi / 2)
    assert list(poses) == ["leo", "turtle1", "turtle3"]  # turtlesim's map is by name


def test_a_command_that_is_not_a_number_stops_the_turtle() -> None:
    world = _started()
    world.command("turtle1", math.nan, 0.0, math.inf, 0.0)
    (pose,) = world.update(PERIOD)
    assert (pose.x, pose.theta, pose.linear_velocity) == (SIZE / 2, 0.0, 0.0)


def test_the_picture_draws_each_turtle_on_the_canvas() -> None:
    world = _started()
    picture = world.image()
    assert picture.shape == (500, 500, 3)
    centre = round(SIZE / 2 * 45)
    assert tuple(picture[centre, centre]) != BACKGROUND
    assert tuple(picture[centre, centre + 13]) != BACKGROUND  # the head, facing +x
    assert tuple(picture[centre, centre - 14]) == BACKGROUND
    assert (world.canvas == BACKGROUND).all()  # the turtles are not on the trails' canvas
