"""The base of every display: rviz's properties, status, enable box, and its message filter.

A display that draws stamped messages (a scan, a path, markers…) draws each one with the
transform at its stamp, as rviz's tf message filter does: a message waits in a queue (Queue
Size) until the transform at its stamp is known, and is dropped — with the reason in the
display's status — when newer messages push it out or its stamp is older than TF keeps. What
it drew then stays fixed in the fixed frame, so a scan taken while the robot turns lands on the
walls. Displays of unstamped state (the map, the robot, TF frames) follow the latest transform.
"""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar, Literal

import numpy as np
import numpy.typing as npt

from belvedere.description.urdf import RobotModel
from belvedere.errors import BelvedereError
from belvedere.graph import NS, Node, Subscription
from belvedere.msgs import short
from belvedere.packages import PackageIndex
from belvedere.tf import TFBuffer, TFError, TFExtrapolationError, Transform, wxyz_from_xyzw
from belvedere.viewer._rviz import parse_color
from belvedere.viewer._status import Level, Status

__all__ = ["Display", "DisplayContext", "Prop", "color_tuple", "transform_points"]

PropKind = Literal["bool", "float", "int", "color", "choice", "text", "topic", "frame"]
RGB = tuple[int, int, int]


@dataclass(frozen=True)
class Prop:
    """One of a display's properties, named as rviz names it in the panel and in ``.rviz``."""

    name: str
    default: Any
    kind: PropKind
    options: tuple[str, ...] = ()
    low: float = 0.0
    high: float = 1.0
    step: float = 0.01


@dataclass
class DisplayContext:
    """What displays share: the viewer's node, scene, TF and the robot's description."""

    node: Node
    scene: Any
    gui: Any
    buffer: TFBuffer
    topic_type: Callable[[str], str | None]
    """The type of a topic on the graph (here or in another process), None if unknown."""
    model: RobotModel | None = None
    packages: PackageIndex | None = None
    docked: list[Any] = field(default_factory=list)
    """The image panels docked beside the 3D view, top first: a new one goes below them."""

    def now_ns(self) -> int:
        return self.node.now_ns()


def line_style(values: Mapping[str, Any]) -> dict[str, Any]:
    """viser's line thickness for rviz's Line Style: "Lines" are one pixel wide whatever the
    distance, "Billboards" are ``Line Width`` metres wide."""
    if values.get("Line Style", "Lines") == "Billboards":
        return {"thickness": float(values.get("Line Width", 0.03)), "thickness_units": "world"}
    return {"thickness": 1.5, "thickness_units": "screen"}


def color_tuple(value: Any) -> RGB:
    """A colour as rviz writes it (``"255; 0; 0"``) or as a sequence of three numbers."""
    try:
        if isinstance(value, str):
            return parse_color(value)
        r, g, b = (max(0, min(255, round(float(p)))) for p in value)
    except (TypeError, ValueError):
        msg = f"a colour is three numbers 0-255 ('255; 0; 0'), not {value!r}"
        raise BelvedereError(msg) from None
    return (r, g, b)


def transform_points(pose: Transform, points: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """(N, 3) points in a frame → the same points in the frame ``pose`` is expressed in."""
    m = pose.matrix()
    out: npt.NDArray[np.float64] = points @ m[:3, :3].T + m[:3, 3]
    return out


def _stamp_ns(msg: Any) -> int:
    header = getattr(msg, "header", None)
    if header is None:
        return 0
    stamp = header.stamp
    return int(stamp.sec) * NS + int(stamp.nanosec)


class Display:
    """One display of the Displays panel: ``name`` of type :attr:`type_name`."""

    cls: ClassVar[str] = ""
    """rviz's class name (``rviz/LaserScan``)."""
    type_name: ClassVar[str] = ""
    """What rviz's Add dialog calls it."""
    msg_type: ClassVar[str] = ""
    """The message type it subscribes to; empty for displays without a topic."""
    props: ClassVar[tuple[Prop, ...]] = ()
    stamped: ClassVar[bool] = True
    """Draw each message once with the transform at its stamp (else :meth:`update` each
    frame with the latest transform)."""
    default_topic: ClassVar[str] = ""

    def __init__(
        self,
        ctx: DisplayContext,
        name: str,
        *,
        topic: str | None = None,
        values: Mapping[str, Any] | None = None,
        enabled: bool = True,
    ) -> None:
        self.ctx = ctx
        self.name = name
        self.status = Status()
        self.draw_lock = threading.RLock()
        """Held while drawing (render thread) and while a property change or a reset takes
        the drawing apart (the panel's threads): a frame never writes to a removed node."""
        self.values: dict[str, Any] = {p.name: p.default for p in self.all_props()}
        for key, value in (values or {}).items():
            self.set_value(key, value)
        if self.msg_type:
            self.values["Topic"] = topic or self.values.get("Topic") or self.default_topic
        self.enabled = enabled
        self.lock = threading.Lock()
        self.pending: deque[Any] = deque()
        self.latest: Any = None
        self.received = 0
        self.dropped_reason: str | None = None
        self.handles: dict[str, Any] = {}
        self.subscription: Subscription | None = None
        self.source: Any = None
        """The ``.rviz`` entry it was read from (kept when the config is saved again)."""
        self.groups: tuple[Any, ...] = ()
        """The ``rviz/Group`` entries (outermost first) the display was read inside."""
        self.fixed = ""
        """The fixed frame of the last frame drawn."""
        if self.msg_type:
            self.status.set("Topic", Level.WARN, "No messages received")
        if enabled:
            self.on_enable()

    # --- properties ------------------------------------------------------------------------------
    @classmethod
    def all_props(cls) -> tuple[Prop, ...]:
        common: tuple[Prop, ...] = ()
        if cls.msg_type:
            common = (
                Prop("Topic", cls.default_topic, "topic"),
                Prop("Queue Size", 10, "int", low=1, high=100, step=1),
            )
        return common + cls.props

    def set_value(self, key: str, value: Any) -> None:
        """Set a property from the panel or a config (rviz's spelling of values)."""
        prop = next((p for p in self.all_props() if p.name == key), None)
        if prop is None:
            self.values[key] = value  # kept for saving, as rviz keeps what it does not know
            return
        if prop.kind == "color":
            value = color_tuple(value)
        elif prop.kind == "bool":
            value = value if isinstance(value, bool) else str(value).lower() == "true"
        elif prop.kind in ("float", "int"):
            try:
                value = float(value) if prop.kind == "float" else round(float(value))
            except (TypeError, ValueError):
                msg = f"display {self.name!r}: {key} is a number, not {value!r}"
                raise BelvedereError(msg) from None
        else:
            value = str(value)
        with self.draw_lock:
            old = self.values.get(key)
            self.values[key] = value
            if key == "Topic" and old != value and getattr(self, "enabled", False):
                self.resubscribe()
            if hasattr(self, "handles") and old != value:
                self.changed(key)

    def changed(self, key: str) -> None:
        """A property changed (subclasses redraw what depends on it)."""

    @property
    def rviz_class(self) -> str:
        return self.cls

    @property
    def topic(self) -> str:
        return str(self.values.get("Topic", ""))

    @property
    def level(self) -> Level:
        return self.status.level if self.enabled else Level.OK

    # --- enable, subscribe -----------------------------------------------------------------------
    def set_enabled(self, enabled: bool) -> None:
        if enabled == self.enabled:
            return
        self.enabled = enabled
        if enabled:
            self.on_enable()
        else:
            self.on_disable()

    def on_enable(self) -> None:
        if self.msg_type:
            self.subscribe()
        self.show(True)

    def on_disable(self) -> None:
        self.unsubscribe()
        self.show(False)

    def show(self, visible: bool) -> None:
        for handle in self.handles.values():
            handle.visible = visible

    def subscribe(self) -> None:
        topic = self.topic
        if not topic:
            self.status.set("Topic", Level.ERROR, "Error subscribing: Empty topic name")
            return
        found = self.ctx.topic_type(topic)
        if found is not None and short(found) != short(self.msg_type):
            self.status.set(
                "Topic",
                Level.ERROR,
                f"Topic [{topic}] is of type [{short(found)}], "
                f"this display shows [{short(self.msg_type)}]",
            )
            return
        try:
            self.subscription = self.ctx.node.subscribe(
                topic, self.msg_type, self.on_message, queue_size=10
            )
        except BelvedereError as err:
            self.status.set("Topic", Level.ERROR, f"Error subscribing: {err.message}")
            return
        self.status.set("Topic", Level.WARN, "No messages received")

    def unsubscribe(self) -> None:
        if self.subscription is not None:
            self.subscription.unregister()
            self.subscription = None

    def resubscribe(self) -> None:
        self.unsubscribe()
        self.reset()
        self.received = 0
        self.subscribe()

    # --- messages (executor thread) --------------------------------------------------------------
    def on_message(self, msg: Any) -> None:
        with self.lock:
            self.received += 1
            if self.stamped:
                self.pending.append(msg)
                while len(self.pending) > max(1, int(self.values.get("Queue Size", 10))):
                    old = self.pending.popleft()
                    self.dropped_reason = self._failure(old, None)
            else:
                self.latest = msg

    # --- drawing (render thread) -----------------------------------------------------------------
    def render(self, fixed: str) -> None:
        """Draw what came since the last frame (render thread)."""
        with self.draw_lock:
            self._render(fixed)

    def _render(self, fixed: str) -> None:
        if not self.enabled:
            return
        self.fixed = fixed
        if self.msg_type and self.received:
            self.status.set("Topic", Level.OK, f"{self.received} messages received")
        if self.stamped:
            for msg, pose in self._ready(fixed):
                self.draw(msg, pose)
            self.tick(fixed)
        else:
            with self.lock:
                msg = self.latest
            self.update(msg, fixed)

    def _ready(self, fixed: str) -> list[tuple[Any, Transform]]:
        """The queued messages whose transform at their stamp is known now, in order; those
        that can never be transformed are dropped with their reason."""
        ready: list[tuple[Any, Transform]] = []
        with self.lock:
            queue = list(self.pending)
            self.pending.clear()
        keep: list[Any] = []
        for msg in queue:
            frame = str(msg.header.frame_id).lstrip("/")
            if not frame:
                self.status.set("Transform", Level.ERROR, "Message has an empty frame_id")
                continue
            try:
                pose = self.ctx.buffer.lookup_transform(fixed, frame, _stamp_ns(msg))
            except TFExtrapolationError as err:
                if "the past." in err.message:
                    self.status.set("Transform", Level.ERROR, self._too_old(msg))
                else:
                    keep.append(msg)  # the transform at its stamp has not come yet
                continue
            except TFError:
                keep.append(msg)  # the frame may still appear (a late static transform)
                continue
            ready.append((msg, pose))
        with self.lock:
            # Newer messages came meanwhile: keep the order, and the queue's bound.
            self.pending.extendleft(reversed(keep))
            while len(self.pending) > max(1, int(self.values.get("Queue Size", 10))):
                self.dropped_reason = self._failure(self.pending.popleft(), fixed)
            reason = self.dropped_reason
            self.dropped_reason = None
        if ready:
            self.status.set("Transform", Level.OK, "Transform OK")
        elif reason is not None:
            self.status.set("Transform", Level.ERROR, reason)
        elif keep:
            self._waiting(keep[0], fixed)
        return ready

    def _unreachable(self, frame: str, fixed: str) -> str | None:
        """Why ``frame`` has no transform to ``fixed`` now, in rviz's words (None: it has)."""
        buffer = self.ctx.buffer
        if frame != fixed and not buffer.frame_exists(frame):
            return f"Frame [{frame}] does not exist"
        if fixed and not buffer.can_transform(fixed, frame):
            return f"No transform from [{frame}] to [{fixed}]"
        return None

    def _failure(self, msg: Any, fixed: str | None) -> str:
        """Why ``msg`` was dropped, in rviz's words."""
        frame = str(msg.header.frame_id).lstrip("/")
        reason = self._unreachable(frame, fixed or self.fixed)
        if reason is not None:
            return f"For frame [{frame}]: {reason}"
        return self._too_old(msg)

    @staticmethod
    def _too_old(msg: Any) -> str:
        frame = str(msg.header.frame_id).lstrip("/")
        return (
            f"Message removed because it is too old "
            f"(frame=[{frame}], stamp=[{_stamp_ns(msg) / NS:.6f}])"
        )

    def _waiting(self, msg: Any, fixed: str) -> None:
        frame = str(msg.header.frame_id).lstrip("/")
        reason = self._unreachable(frame, fixed)
        if reason is not None:
            self.status.set("Transform", Level.ERROR, f"For frame [{frame}]: {reason}")

    def latest_pose(self, frame_id: str, fixed: str) -> Transform | None:
        """The frame's latest pose in the fixed frame (status says why when there is none)."""
        frame = frame_id.lstrip("/") or fixed
        try:
            pose = self.ctx.buffer.lookup_transform(fixed, frame)
        except TFError:
            reason = self._unreachable(frame, fixed) or f"No transform from [{frame}] to [{fixed}]"
            self.status.set("Transform", Level.ERROR, reason)
            return None
        self.status.set("Transform", Level.OK, "Transform OK")
        return pose

    def draw(self, msg: Any, pose: Transform) -> None:
        """Draw a stamped message; ``pose``: its frame in the fixed frame at its stamp."""

    def tick(self, fixed: str) -> None:
        """Once a frame after new messages were drawn (decay, trails)."""

    def update(self, msg: Any, fixed: str) -> None:
        """Draw unstamped state with the latest transform (every frame)."""

    # --- scene -----------------------------------------------------------------------------------
    @property
    def base(self) -> str:
        return f"/displays/{id(self)}"

    def keep(self, key: str, handle: Any, pose: Transform | None = None) -> Any:
        """Keep a scene handle (made as ``base/key``: it replaced the one of that name),
        placed at ``pose`` if given."""
        if pose is not None:
            handle.position = pose.translation
            handle.wxyz = wxyz_from_xyzw(pose.quat_xyzw)
        handle.visible = self.enabled
        self.handles[key] = handle
        return handle

    def forget(self, key: str) -> None:
        handle = self.handles.pop(key, None)
        if handle is not None:
            handle.remove()

    def reset(self) -> None:
        """Clear what was drawn and what waits (rviz's Reset; the fixed frame changed)."""
        with self.draw_lock:
            with self.lock:
                self.pending.clear()
            for key in list(self.handles):
                self.forget(key)
            self.status.clear("Transform")

    def remove(self) -> None:
        self.unsubscribe()
        with self.draw_lock:
            for key in list(self.handles):
                self.forget(key)
