"""The TF buffer: the frame tree over time, with interpolation, as tf2 keeps it."""

from __future__ import annotations

import bisect
from dataclasses import dataclass, field
from typing import Any, Final

from belvedere.errors import BelvedereError
from belvedere.tf._math import Transform

__all__ = ["TFBuffer", "TFError"]

NS: Final = 1_000_000_000


class TFError(BelvedereError):
    """A transform that cannot be looked up: unknown or unconnected frames, or no data then."""


@dataclass
class _Frame:
    parent: str
    static: bool
    stamps: list[int] = field(default_factory=list)
    transforms: list[Transform] = field(default_factory=list)
    updates: int = 0

    def at(self, time_ns: int, child: str) -> Transform:
        if self.static or time_ns == 0:
            return self.transforms[-1]
        i = bisect.bisect_left(self.stamps, time_ns)
        if i < len(self.stamps) and self.stamps[i] == time_ns:
            return self.transforms[i]
        if i == 0 or i == len(self.stamps):
            span = f"[{self.stamps[0] / NS:.3f}, {self.stamps[-1] / NS:.3f}] s"
            direction = "past" if i == 0 else "future"
            msg = (
                f"lookup at t={time_ns / NS:.3f} s would extrapolate into the {direction}: "
                f"data for {self.parent} -> {child} covers {span}"
            )
            raise TFError(msg)
        t0, t1 = self.stamps[i - 1], self.stamps[i]
        return self.transforms[i - 1].interpolate(self.transforms[i], (time_ns - t0) / (t1 - t0))


class TFBuffer:
    """Transforms by child frame, each with its parent and a time-stamped history."""

    def __init__(self, *, cache_time: float = 10.0) -> None:
        self.cache_ns = round(cache_time * NS)
        self._frames: dict[str, _Frame] = {}

    def set_transform(
        self, parent: str, child: str, transform: Transform, stamp_ns: int, *, static: bool = False
    ) -> None:
        parent, child = parent.lstrip("/"), child.lstrip("/")
        if not parent or not child or parent == child:
            msg = f"invalid transform {parent!r} -> {child!r}"
            raise TFError(msg)
        frame = self._frames.get(child)
        if frame is None or frame.parent != parent or frame.static != static:
            frame = self._frames[child] = _Frame(parent, static)
        frame.updates += 1
        if static:
            frame.stamps[:] = [stamp_ns]
            frame.transforms[:] = [transform]
            return
        i = bisect.bisect_right(frame.stamps, stamp_ns)
        if i and frame.stamps[i - 1] == stamp_ns:
            frame.transforms[i - 1] = transform
        else:
            frame.stamps.insert(i, stamp_ns)
            frame.transforms.insert(i, transform)
        cutoff = frame.stamps[-1] - self.cache_ns
        drop = bisect.bisect_left(frame.stamps, cutoff)
        if drop:
            del frame.stamps[:drop]
            del frame.transforms[:drop]

    def set_message(self, msg: Any, *, static: bool = False) -> None:
        """Add a ``tf2_msgs/TFMessage`` (or one ``TransformStamped``)."""
        items = msg.transforms if hasattr(msg, "transforms") else [msg]
        for t in items:
            tr, rot = t.transform.translation, t.transform.rotation
            stamp = t.header.stamp.sec * NS + t.header.stamp.nanosec
            self.set_transform(
                t.header.frame_id,
                t.child_frame_id,
                Transform((tr.x, tr.y, tr.z), (rot.x, rot.y, rot.z, rot.w)),
                stamp,
                static=static,
            )

    # --- queries -------------------------------------------------------------------------------
    def frames(self) -> set[str]:
        out = set(self._frames)
        out.update(f.parent for f in self._frames.values())
        return out

    def parent(self, frame: str) -> str | None:
        f = self._frames.get(frame.lstrip("/"))
        return f.parent if f else None

    def _chain(self, frame: str) -> list[str]:
        chain = [frame]
        seen = {frame}
        while (f := self._frames.get(chain[-1])) is not None:
            if f.parent in seen:
                msg = f"the frame tree has a loop through {f.parent!r}"
                raise TFError(msg)
            chain.append(f.parent)
            seen.add(f.parent)
        return chain

    def _latest_common(self, frames: list[str]) -> int:
        stamps = [
            self._frames[f].stamps[-1]
            for f in frames
            if f in self._frames and not self._frames[f].static
        ]
        return min(stamps) if stamps else 0

    def lookup_transform(self, target: str, source: str, time_ns: int = 0) -> Transform:
        """``T_target_source`` at ``time_ns`` (0: the latest time all frames share)."""
        target, source = target.lstrip("/"), source.lstrip("/")
        known = self.frames()
        for name in (target, source):
            if name not in known:
                listing = ", ".join(sorted(known)) or "(none yet)"
                msg = f"frame {name!r} does not exist (frames: {listing})"
                raise TFError(msg)
        up_source, up_target = self._chain(source), self._chain(target)
        common = next((f for f in up_source if f in up_target), None)
        if common is None:
            msg = (
                f"frames {source!r} and {target!r} are not connected: {source!r} is in the tree "
                f"of {up_source[-1]!r}, {target!r} in the tree of {up_target[-1]!r}"
            )
            raise TFError(msg)
        path_s = up_source[: up_source.index(common)]
        path_t = up_target[: up_target.index(common)]
        if time_ns == 0:
            time_ns = self._latest_common(path_s + path_t)
        t_common_source = Transform()
        for frame in reversed(path_s):
            t_common_source = t_common_source @ self._frames[frame].at(time_ns, frame)
        t_common_target = Transform()
        for frame in reversed(path_t):
            t_common_target = t_common_target @ self._frames[frame].at(time_ns, frame)
        return t_common_target.inverse() @ t_common_source

    def can_transform(self, target: str, source: str, time_ns: int = 0) -> bool:
        try:
            self.lookup_transform(target, source, time_ns)
        except TFError:
            return False
        return True

    def tree(self, now_ns: int | None = None) -> str:
        """The frame tree as text (like view_frames): parent, rate and last update."""
        children: dict[str, list[str]] = {}
        for child, f in self._frames.items():
            children.setdefault(f.parent, []).append(child)
        roots = sorted(self.frames() - set(self._frames))
        lines: list[str] = []

        def walk(frame: str, depth: int) -> None:
            f = self._frames.get(frame)
            detail = ""
            if f is not None:
                if f.static:
                    detail = " [static]"
                else:
                    span = (f.stamps[-1] - f.stamps[0]) / NS if len(f.stamps) > 1 else 0.0
                    rate = (len(f.stamps) - 1) / span if span > 0 else 0.0
                    age = (
                        f" , {((now_ns or f.stamps[-1]) - f.stamps[-1]) / NS:.3f} s ago"
                        if now_ns
                        else ""
                    )
                    detail = f" [{rate:.1f} Hz, last {f.stamps[-1] / NS:.3f} s{age}]"
            lines.append("  " * depth + frame + detail)
            for c in sorted(children.get(frame, [])):
                walk(c, depth + 1)

        for root in roots:
            walk(root, 0)
        return "\n".join(lines)
