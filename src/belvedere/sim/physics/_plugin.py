"""What every Gazebo plugin stand-in shares: its parameters, its node, its place in the step.

A plugin is read from ``<plugin filename=… name=…>`` (in a robot's ``<gazebo>`` or in a
``<sensor>``). It may add actuators or cameras before the model is compiled (``prepare``),
finds its ids after every compile (``bind``), and runs after every physics step (``update``),
deciding itself, from its update rate, whether to act.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from typing import Final

import mujoco
import numpy as np

from belvedere.description.urdf import GazeboPlugin, XmlData
from belvedere.errors import SourceLocation
from belvedere.graph import NS, Graph, Node
from belvedere.sim.physics._builder import RobotBuild
from belvedere.sim.physics._engine import Engine
from belvedere.sim.physics._spec import ModelError

__all__ = ["IDLE", "Plugin", "PluginContext", "RateGate"]

IDLE: Final = 2**62
"""What :meth:`Plugin.next_update_ns` says when the plugin has nothing to do (nobody listens)."""

logger = logging.getLogger("belvedere.physics")


@dataclass
class PluginContext:
    engine: Engine
    graph: Graph
    robot: RobotBuild
    name: str
    filename: str
    params: tuple[XmlData, ...]
    source: SourceLocation | None
    reference: str | None = None
    """The link the plugin's ``<gazebo reference>`` or sensor belongs to."""
    sensor: XmlData | None = None

    @classmethod
    def of(
        cls,
        engine: Engine,
        graph: Graph,
        robot: RobotBuild,
        plugin: GazeboPlugin,
        *,
        reference: str | None = None,
        sensor: XmlData | None = None,
    ) -> PluginContext:
        return cls(
            engine,
            graph,
            robot,
            plugin.name,
            plugin.filename,
            plugin.params,
            plugin.source.best,
            reference,
            sensor,
        )


class Plugin:
    """Base of the plugin stand-ins."""

    NAMESPACE_DEFAULTS_TO_MODEL = False
    """Plugins built on gazebo_ros's GazeboRos helper (diff drive, joint state publisher)
    default ``robotNamespace`` to the model's name; the others to the root namespace."""

    def __init__(self, ctx: PluginContext) -> None:
        self.ctx = ctx
        self.engine = ctx.engine
        self.robot = ctx.robot
        seed = ctx.graph.executor.random.getrandbits(64)
        self.rng = np.random.default_rng(seed)
        """Seeded from the graph's seed: the same seed, the same noise."""
        self.active = True
        """False once its robot is deleted."""

    # --- parameters ------------------------------------------------------------------------------
    def text(self, tag: str, default: str | None = None) -> str | None:
        for p in self.ctx.params:
            if p.tag == tag:
                return p.text.strip()
        return default

    def number(self, tag: str, default: float) -> float:
        value = self.text(tag)
        if value is None or value == "":
            return default
        try:
            result = float(value)
        except ValueError:
            msg = f"plugin {self.ctx.name!r}: <{tag}> expects a number, got {value!r}"
            raise ModelError(msg, self._where(tag)) from None
        if not math.isfinite(result):
            msg = f"plugin {self.ctx.name!r}: <{tag}> must be finite, got {value!r}"
            raise ModelError(msg, self._where(tag))
        return result

    def flag(self, tag: str, default: bool) -> bool:
        value = self.text(tag)
        if value is None or value == "":
            return default
        lowered = value.lower()
        if lowered in ("1", "true"):
            return True
        if lowered in ("0", "false"):
            return False
        msg = f"plugin {self.ctx.name!r}: <{tag}> expects true or false, got {value!r}"
        raise ModelError(msg, self._where(tag))

    def _where(self, tag: str) -> SourceLocation | None:
        for p in self.ctx.params:
            if p.tag == tag and p.source.best is not None:
                return p.source.best
        return self.ctx.source

    def namespace(self) -> str:
        ns = self.text("robotNamespace")
        if ns is None:
            ns = self.robot.name if self.NAMESPACE_DEFAULTS_TO_MODEL else "/"
        return "/" + "/".join(part for part in ns.split("/") if part)

    def make_node(self, suffix: str = "") -> Node:
        base = "gazebo_" + "".join(c if c.isalnum() else "_" for c in self.ctx.name)
        name = base + suffix
        ns = self.namespace()
        taken = set(self.ctx.graph.nodes)
        candidate, i = name, 1
        while (ns.rstrip("/") + "/" + candidate) in taken:
            i += 1
            candidate = f"{name}_{i}"
        return self.ctx.graph.create_node(candidate, namespace=ns)

    # --- lifecycle -------------------------------------------------------------------------------
    def prepare(self, spec: mujoco.MjSpec) -> None:
        """Add what the plugin needs to the model before it is compiled."""

    def bind(self) -> None:
        """Find ids after a compile."""

    def update(self, now_ns: int) -> None:
        """After every physics step."""

    def next_update_ns(self, now_ns: int) -> int | None:
        """The earliest simulated time at which :meth:`update` would act; the simulation runs
        the steps before it in one batch without calling it. None: it acts at every step."""
        return None

    def reset(self) -> None:
        """After the world was reset."""

    def joint_names(self) -> tuple[str, ...]:
        """Joints whose states this plugin publishes on joint_states."""
        return ()


class RateGate:
    """When a rate-limited plugin or sensor acts, as Gazebo decides it: on the first step at or
    past the next due time, with the due time advanced by whole periods from the previous one
    — the overshoot of a step that lands late is carried into the next period, so the rate
    averages the requested one (a 5.5 Hz laser on 10 ms steps fires after 190 or 180 ms,
    5.5 times a second, not every 190 ms). It never fires twice in one step: after a gap of
    more than a period (a pause, a reset, a rate above the step rate, a sensor nobody
    listened to) it starts over from now. ``rate <= 0``: every step.

    ``strict``: the plugins' ``elapsed > period`` (gazebo_ros_diff_drive and its peers) rather
    than the sensors' ``elapsed >= period``. ``immediate``: fire on the first call (sensors
    measure at once) rather than a period after ``now_ns``.
    """

    def __init__(
        self, rate: float, now_ns: int, *, strict: bool = True, immediate: bool = False
    ) -> None:
        self.period_ns = round(NS / rate) if rate > 0 else 0
        self.strict = strict
        self.immediate = immediate
        self.last_ns: int | None = None if immediate else now_ns

    def due(self, now_ns: int) -> bool:
        if self.period_ns == 0 or self.last_ns is None:
            self.last_ns = now_ns
            return True
        if not self._passed(now_ns - self.last_ns):
            return False
        self.last_ns += self.period_ns
        if self._passed(now_ns - self.last_ns):  # still due: fell behind, start over
            self.last_ns = now_ns
        return True

    def _passed(self, elapsed_ns: int) -> bool:
        if self.strict:
            return elapsed_ns > self.period_ns
        return elapsed_ns >= self.period_ns

    def next_ns(self) -> int | None:
        """The earliest time at which :meth:`due` holds (None: every step, or now)."""
        if self.period_ns == 0 or self.last_ns is None:
            return None
        return self.last_ns + self.period_ns + (1 if self.strict else 0)

    def reset(self, now_ns: int) -> None:
        self.last_ns = None if self.immediate else now_ns
