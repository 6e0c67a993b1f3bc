"""The controller_manager: the controller types it knows, the services that load, start and
stop controllers, and ``controller_manager spawner``, which calls them."""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from belvedere.graph import Node
from belvedere.sim.physics._ros_control._controllers import (
    Controller,
    EffortPid,
    ForwardCommand,
    JointStateController,
    TrajectoryController,
)
from belvedere.sim.physics._ros_control._diff_drive import DiffDriveController
from belvedere.sim.physics._ros_control._hardware import JointHandle, RobotHardware
from belvedere.sim.physics._spec import ModelError

__all__ = ["CONTROLLER_TYPES", "ControllerManager", "spawner"]

logger = logging.getLogger("belvedere.ros_control")


def _forward(interface: str) -> Callable[[ControllerManager, str, dict[str, Any]], Controller]:
    def make(manager: ControllerManager, name: str, params: dict[str, Any]) -> Controller:
        controller = ForwardCommand(manager, name, params)
        controller.interface = interface
        return controller

    return make


CONTROLLER_TYPES: dict[str, Callable[[ControllerManager, str, dict[str, Any]], Controller]] = {
    "joint_state_controller/JointStateController": JointStateController,
    "position_controllers/JointPositionController": _forward("position"),
    "velocity_controllers/JointVelocityController": _forward("velocity"),
    "effort_controllers/JointEffortController": _forward("effort"),
    "effort_controllers/JointPositionController": lambda m, n, p: EffortPid(m, n, p, on="position"),
    "effort_controllers/JointVelocityController": lambda m, n, p: EffortPid(m, n, p, on="velocity"),
    "position_controllers/JointTrajectoryController": lambda m, n, p: TrajectoryController(
        m, n, p, interface="position"
    ),
    "effort_controllers/JointTrajectoryController": lambda m, n, p: TrajectoryController(
        m, n, p, interface="effort"
    ),
    "velocity_controllers/JointTrajectoryController": lambda m, n, p: TrajectoryController(
        m, n, p, interface="velocity"
    ),
    "diff_drive_controller/DiffDriveController": DiffDriveController,
}


@dataclass
class ControllerManager:
    """The controllers of one robot, and the services that load, start and stop them."""

    plugin: RobotHardware
    namespace: str
    handles: dict[str, JointHandle]
    controllers: dict[str, Controller] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.graph = self.plugin.ctx.graph
        self.node: Node = self.graph.create_node("controller_manager", namespace=self.namespace)
        for service, srv, handler in (
            ("load_controller", "LoadController", self._load),
            ("unload_controller", "UnloadController", self._unload),
            ("switch_controller", "SwitchController", self._switch),
            ("list_controllers", "ListControllers", self._list),
        ):
            self.node.service(
                f"controller_manager/{service}", f"controller_manager_msgs/{srv}", handler
            )

    def wheel_geometry(self, left: str, right: str) -> tuple[float, float]:
        return self.plugin.wheel_geometry(left, right)

    def load(self, name: str) -> Controller:
        if name in self.controllers:
            msg = f"controller {name!r} is already loaded"
            raise ModelError(msg)
        params = self.graph.params.get(f"{self.namespace.rstrip('/')}/{name}", None)
        if not isinstance(params, dict) or "type" not in params:
            msg = (
                f"controller {name!r}: no parameter {self.namespace.rstrip('/')}/{name}/type "
                "(load the controllers' YAML into the parameter server first)"
            )
            raise ModelError(msg)
        factory = CONTROLLER_TYPES.get(str(params["type"]))
        if factory is None:
            known = ", ".join(sorted(CONTROLLER_TYPES))
            msg = f"controller {name!r}: unknown type {params['type']!r} (known: {known})"
            raise ModelError(msg)
        controller = factory(self, name, params)
        for joint in controller.joints():
            controller.handle(joint)  # checks the joint and its interface now
        self.controllers[name] = controller
        return controller

    def start(self, name: str) -> None:
        controller = self.controllers[name]
        for joint in controller.joints():
            handle = controller.handle(joint)
            if handle.claimed_by not in (None, name):
                msg = (
                    f"controller {name!r}: joint {joint!r} is already claimed by "
                    f"{handle.claimed_by!r}"
                )
                raise ModelError(msg)
        for joint in controller.joints():
            controller.handle(joint).claimed_by = name
        controller.start()

    def stop(self, name: str) -> None:
        controller = self.controllers[name]
        controller.stop()
        for joint in controller.joints():
            handle = controller.handle(joint)
            if handle.claimed_by == name:
                handle.claimed_by = None
                handle.command = None

    def update(self, now_ns: int, dt: float) -> None:
        for controller in self.controllers.values():
            if controller.running:
                controller.update(now_ns, dt)

    # --- services --------------------------------------------------------------------------------
    def _load(self, req: Any) -> dict[str, Any]:
        try:
            self.load(req.name)
        except ModelError as err:
            logger.error("%s", err.message)
            return {"ok": False}
        return {"ok": True}

    def _unload(self, req: Any) -> dict[str, Any]:
        controller = self.controllers.get(req.name)
        if controller is None or controller.running:
            return {"ok": False}
        del self.controllers[req.name]
        return {"ok": True}

    def _switch(self, req: Any) -> dict[str, Any]:
        try:
            for name in req.stop_controllers:
                if name in self.controllers:
                    self.stop(name)
                elif req.strictness == 2:
                    return {"ok": False}
            for name in req.start_controllers:
                if name not in self.controllers:
                    if req.strictness == 2:
                        return {"ok": False}
                    continue
                self.start(name)
        except ModelError as err:
            logger.error("%s", err.message)
            return {"ok": False}
        return {"ok": True}

    def _list(self, _: Any) -> dict[str, Any]:
        def interface(c: Controller) -> str:
            # ros_control names the interface by its C++ type; a state controller reads the
            # JointStateInterface, which claims nothing
            if not c.interface:
                return "hardware_interface::JointStateInterface"
            return f"hardware_interface::{c.interface.capitalize()}JointInterface"

        return {
            "controller": [
                {
                    "name": name,
                    "state": "running" if c.running else "stopped",
                    "type": str(c.params.get("type", "")),
                    "claimed_resources": [
                        {
                            "hardware_interface": interface(c),
                            "resources": c.joints(),
                        }
                    ],
                }
                for name, c in self.controllers.items()
            ]
        }


def spawner(node: Node, argv: list[str], *, namespace: str = "/") -> list[str]:
    """``controller_manager spawner NAME…``: load and start controllers (``--stopped``: load
    only; ``--namespace NS``). Returns the names started."""
    names: list[str] = []
    stopped = False
    ns = namespace
    words = list(argv)
    while words:
        word = words.pop(0)
        if word == "--stopped":
            stopped = True
        elif word in ("--namespace", "--timeout"):
            value = words.pop(0) if words else ""
            if word == "--namespace":
                ns = value
        elif word.startswith("--namespace="):
            ns = word.split("=", 1)[1]
        elif word.startswith("--") or word == "--shutdown-timeout":
            continue
        else:
            names.append(word)
    base = "/" + "/".join(p for p in ns.split("/") if p)
    prefix = base.rstrip("/") + "/controller_manager"
    for name in names:
        ok = node.call_service(
            f"{prefix}/load_controller", "controller_manager_msgs/LoadController", {"name": name}
        )
        if not ok.ok:
            msg = f"spawner: failed to load controller {name!r} (see the error above)"
            raise ModelError(msg)
    if not stopped and names:
        ok = node.call_service(
            f"{prefix}/switch_controller",
            "controller_manager_msgs/SwitchController",
            {"start_controllers": names, "stop_controllers": [], "strictness": 2},
        )
        if not ok.ok:
            msg = f"spawner: failed to start controllers {names}"
            raise ModelError(msg)
    return names
