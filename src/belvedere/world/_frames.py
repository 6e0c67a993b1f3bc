"""SDF frame graphs: the frames of one scope (a model, or the world) and how they hang together.

SDF 1.7 makes every link, joint, explicit ``<frame>`` and nested model a frame, next to the
scope's own frame (``__model__`` in a model, ``world`` in a world). Two graphs join them:

* the *pose graph*: each frame's pose is written relative to another frame of the scope
  (``<pose relative_to=…>``, or a default that depends on the kind of element);
* the *attached-to graph*: each frame moves with another (a joint with its child link, a
  ``<frame>`` with its ``attached_to``, the model frame with its canonical link) until a link,
  or the world, ends the chain.

Both must be free of cycles and name only frames of the scope; each is resolved lazily and
remembered, walking a chain with a list rather than recursion (a chain is as long as the file
makes it). A nested model's frames join its parent's graph under ``name::…``.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from belvedere.description.urdf import Pose, transform
from belvedere.errors import SourceLocation
from belvedere.world._model import SDFError
from belvedere.world._poses import from_matrix

__all__ = ["FrameGraph", "Matrix4"]

Matrix4 = npt.NDArray[np.float64]


@dataclass(slots=True)
class _Frame:
    name: str
    kind: str
    """``link``, ``joint``, ``frame``, ``model`` (nested or in a world) or the scope's own."""
    pose: Matrix4
    """As written: the frame's pose in ``relative_to``."""
    relative_to: str | None
    """None only for the scope's own frame, the root of the pose graph."""
    attached_to: str | None
    """None: the frame ends its attached-to chain (a link, a world model, the world)."""
    source: SourceLocation | None


class FrameGraph:
    """The frames of one scope, resolved on demand.

    Args:
        scope: How messages name the scope, e.g. ``model 'mrobot'`` or ``world 'default'``.
        root: The scope's own frame: ``__model__`` or ``world``.
    """

    def __init__(self, scope: str, root: str, *, legacy: bool = False) -> None:
        self.scope = scope
        self.root = root
        self.legacy = legacy
        self.frames: dict[str, _Frame] = {
            root: _Frame(root, root, np.eye(4), None, None, None),
        }
        self._in_root: dict[str, Matrix4] = {root: np.eye(4)}
        self._static: set[str] = set()
        """Nested models fixed to the world: attached-to chains through them end there."""
        self._body: dict[str, str] = {}

    def __contains__(self, name: str) -> bool:
        return name in self.frames

    def kind(self, name: str) -> str | None:
        frame = self.frames.get(name)
        return frame.kind if frame is not None else None

    def names(self, kind: str | None = None) -> list[str]:
        """The frames' names in the order they were added (of one kind if given)."""
        return [n for n, f in self.frames.items() if kind is None or f.kind == kind]

    # --- building ----------------------------------------------------------------------------
    def add(
        self,
        name: str,
        kind: str,
        pose: Pose | Matrix4,
        *,
        relative_to: str,
        attached_to: str | None,
        source: SourceLocation | None,
    ) -> bool:
        """Add a frame; a name already taken in this scope is an error naming both places.

        Before SDF 1.7 only siblings of one kind needed names of their own: there a joint
        named like a link is kept out of the graph (False), and ``relative_to`` finds the
        link."""
        taken = self.frames.get(name)
        if taken is not None:
            first = f" (the first at {taken.source})" if taken.source else ""
            if taken.kind == kind:
                msg = f"two {kind}s of {self.scope} are named {name!r}{first}"
                raise SDFError(msg, source)
            if self.legacy:
                return False
            msg = f"{self.scope} has a {taken.kind} and a {kind} both named {name!r}{first}"
            raise SDFError(
                msg,
                source,
                hint="since SDF 1.7 links, joints, frames and nested models share one "
                "namespace in their model (and models and frames in a world)",
            )
        matrix = pose if isinstance(pose, np.ndarray) else transform(pose)
        self.frames[name] = _Frame(name, kind, matrix, relative_to, attached_to, source)
        return True

    def attach_root(self, attached_to: str | None) -> None:
        """Attach the scope's own frame (a model frame to its canonical link)."""
        self.frames[self.root].attached_to = attached_to

    def add_nested(
        self,
        name: str,
        inner: FrameGraph,
        pose: Matrix4,
        *,
        relative_to: str,
        static: bool,
        source: SourceLocation | None,
    ) -> None:
        """Add a nested model's frame ``name`` (its pose given in ``relative_to``) and every
        frame of ``inner`` under ``name::…``, placed in the nested model's frame."""
        body = None if static else inner.body(inner.root)
        if static or body is None:
            self._static.add(name)
        self.add(
            name,
            "model",
            pose,
            relative_to=relative_to,
            attached_to=None if body is None else f"{name}::{body}",
            source=source,
        )
        for inner_name, frame in inner.frames.items():
            scoped = f"{name}::{inner_name}"
            if inner_name == inner.root:
                self.frames[scoped] = _Frame(scoped, "alias", np.eye(4), name, name, source)
                continue
            inner_body = inner.body(inner_name)
            self.frames[scoped] = _Frame(
                scoped,
                frame.kind,
                inner.in_root(inner_name),
                name,
                None
                if inner_body == inner_name
                else name
                if inner_body is None
                else f"{name}::{inner_body}",
                frame.source,
            )

    # --- the pose graph ------------------------------------------------------------------------
    def in_root(
        self, name: str, *, asked_by: str = "", at: SourceLocation | None = None
    ) -> Matrix4:
        """The pose of frame ``name`` in the scope's frame. ``asked_by`` (e.g. ``pose of
        visual 'v'``) and ``at`` say who named it, for the error if it is not a frame here."""
        done = self._in_root
        if name in done:
            return done[name]
        if name not in self.frames:
            raise self._unknown(asked_by or "a pose", "relative_to", name, at)
        chain: list[str] = []
        on_chain: set[str] = set()
        current = name
        while current not in done:
            frame = self.frames[current]
            if current in on_chain:
                cycle = [*chain[chain.index(current) :], current]
                msg = f"pose of {current!r} is relative to itself through {' -> '.join(cycle)}"
                raise SDFError(
                    msg, frame.source, hint="the pose graph must lead to the " + self.root
                )
            on_chain.add(current)
            chain.append(current)
            target = frame.relative_to
            assert target is not None  # only the root has none, and it is done
            if target not in self.frames:
                who = f"pose of {frame.kind} {current!r}"
                raise self._unknown(who, "relative_to", target, frame.source)
            current = target
        for waiting in reversed(chain):
            frame = self.frames[waiting]
            assert frame.relative_to is not None
            done[waiting] = done[frame.relative_to] @ frame.pose
        return done[name]

    def pose(self, name: str) -> Pose:
        """The pose of frame ``name`` in the scope's frame."""
        return from_matrix(self.in_root(name))

    def resolve(
        self, pose: Pose, relative_to: str, *, asked_by: str, at: SourceLocation | None
    ) -> Matrix4:
        """A pose written relative to frame ``relative_to``, in the scope's frame."""
        result: Matrix4 = self.in_root(relative_to, asked_by=asked_by, at=at) @ transform(pose)
        return result

    def between(self, frame: str, target: Matrix4) -> Pose:
        """``target`` (in the scope's frame) seen from frame ``frame``."""
        inverse = np.linalg.inv(self.in_root(frame))
        return from_matrix(np.asarray(inverse @ target, dtype=np.float64))

    # --- the attached-to graph --------------------------------------------------------------------
    def body(self, name: str) -> str | None:
        """The frame that ends ``name``'s attached-to chain: a link (or a world model); None
        when the chain ends at the world (a static model, a world frame)."""
        if name in self._body:
            found = self._body[name]
            return found or None
        chain: list[str] = []
        on_chain: set[str] = set()
        current = name
        end: str | None = None
        while True:
            if current in self._body:
                end = self._body[current] or None
                break
            frame = self.frames[current]
            if current in on_chain:
                cycle = [*chain[chain.index(current) :], current]
                msg = f"{frame.kind} {current!r} is attached to itself through {' -> '.join(cycle)}"
                raise SDFError(msg, frame.source, hint="attached_to must lead to a link")
            on_chain.add(current)
            chain.append(current)
            target = frame.attached_to
            if target is None:
                ends_at_world = frame.kind in (self.root, "world") or current in self._static
                end = None if ends_at_world else current
                break
            if target not in self.frames:
                who = f"{frame.kind} {current!r}"
                raise self._unknown(who, "attached_to", target, frame.source)
            current = target
        for waiting in chain:
            self._body[waiting] = end or ""
        return end

    def check(self) -> None:
        """Resolve every frame's pose and body: any cycle or unknown name is an error now."""
        for name in self.frames:  # attached_to first: a frame's pose defaults to it
            self.body(name)
        for name in self.frames:
            self.in_root(name)

    # --- errors ----------------------------------------------------------------------------------
    def _unknown(self, who: str, attribute: str, name: str, at: SourceLocation | None) -> SDFError:
        known = [n for n, f in self.frames.items() if f.kind != "alias"]
        close = difflib.get_close_matches(name, known, n=1)
        shown = ", ".join(known[:24]) + (f", … ({len(known) - 24} more)" if len(known) > 24 else "")
        hint = f"frames of this {self.scope.split(' ')[0]}: {shown}"
        if close:
            hint = f"did you mean {close[0]!r}? " + hint
        if name == "world" and self.root == "__model__":
            hint = "a pose inside a model cannot name the world; " + hint
        msg = f"{who} is {attribute} {name!r}, which is not a frame of {self.scope}"
        return SDFError(msg, at, hint=hint)
