"""The kinematic simulation of one robot, as the course's ArbotiX launch files set it up:
``robot_description``, the fake ArbotiX driver, robot_state_publisher (20 Hz) and
joint_state_publisher, in a namespace of their own if asked.
"""

from __future__ import annotations

import dataclasses
import logging
from typing import Any

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph
from belvedere.sim.kinematic._config import ArbotixConfig, DiffControllerConfig
from belvedere.sim.kinematic._driver import ArbotixDriver
from belvedere.tf import JointStatePublisher, RobotStatePublisher

__all__ = ["KinematicSimulation", "default_config"]

logger = logging.getLogger("belvedere.sim")


def default_config(model: RobotModel) -> ArbotixConfig:
    """A config for a model given none: one ``diff_controller`` whose base frame is the
    model's root link and whose width is the spread of its wheel joints (unused when fake)."""
    wheels = [
        j.origin.xyz[1] for j in model.joints if j.type == "continuous" and "wheel" in j.child
    ]
    width = max(wheels) - min(wheels) if len(wheels) >= 2 else 0.3
    base = DiffControllerConfig(
        name="base_controller",
        ticks_meter=4100.0,
        base_width=round(width, 6) or 0.3,
        base_frame_id=model.root_link.name,
    )
    return ArbotixConfig(sim=True, controllers=(base,))


class DriverControls:
    """The viewer's Simulation folder over fake ArbotiX drivers: Paused, Step and the
    real-time factor act on the graph's clock; Reset puts every driver back at its origin."""

    def __init__(self, graph: Graph, drivers: list[ArbotixDriver] | None = None) -> None:
        self.graph = graph
        self.drivers: list[ArbotixDriver] = list(drivers or [])
        """Those a launch started (each ``arbotix_driver`` node adds its own)."""

    def pause(self, paused: bool) -> None:
        self.graph.executor.pause(paused)

    def step(self) -> None:
        self.graph.executor.step(0.1)

    def reset(self) -> None:
        for driver in self.drivers:
            self.graph.executor.post(driver.reset)

    def set_rtf(self, rtf: float | None) -> None:
        self.graph.executor.set_rtf(rtf)


class KinematicSimulation(DriverControls):
    """A robot moved by the fake ArbotiX driver. Also the viewer's simulation controls."""

    def __init__(
        self,
        graph: Graph,
        model: RobotModel,
        config: ArbotixConfig | None = None,
        *,
        params: dict[str, Any] | None = None,
        namespace: str = "/",
        cmd_vel_timeout: float | None = None,
    ) -> None:
        """``params``: the driver's parameters as loaded (set under ``<ns>/arbotix``);
        ``cmd_vel_timeout`` overrides every base's."""
        self.graph = graph
        self.model = model
        config = dataclasses.replace(config or default_config(model), sim=True)
        if cmd_vel_timeout is not None:
            config = dataclasses.replace(
                config,
                controllers=tuple(
                    dataclasses.replace(c, cmd_vel_timeout=cmd_vel_timeout)
                    if isinstance(c, DiffControllerConfig)
                    else c
                    for c in config.controllers
                ),
            )
        self.namespace = "/" + "/".join(p for p in namespace.split("/") if p)
        prefix = self.namespace.strip("/")
        self.frame_prefix = f"{prefix}/" if prefix else ""
        ns = self.namespace.rstrip("/")
        graph.params.set(f"{ns}/robot_description", model.to_urdf())
        driver_params = dict(params or {})
        driver_params["sim"] = True
        driver_node = graph.create_node("arbotix", namespace=self.namespace, params=driver_params)
        self.driver = ArbotixDriver(driver_node, config, frame_prefix=self.frame_prefix)
        super().__init__(graph, [self.driver])
        self.robot_state_publisher = RobotStatePublisher(
            graph.create_node(
                "robot_state_publisher",
                namespace=self.namespace,
                params={"publish_frequency": 20.0, "tf_prefix": prefix},
            ),
            model,
        )
        self.joint_state_publisher = JointStatePublisher(
            graph.create_node("joint_state_publisher", namespace=self.namespace),
            model,
            # what the driver reports: its servos and its controllers' joints (a
            # diff_controller's base_l_wheel_joint and base_r_wheel_joint)
            exclude={
                *self.driver.servos,
                *(n for c in self.driver.controllers for n in c.joint_names),
            },
        )

    @property
    def odom_frame(self) -> str | None:
        base = self.driver.base
        return base.odom_frame if base else None
