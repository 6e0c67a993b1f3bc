"""A model's frame graph: each frame's pose in the model frame, from ``relative_to`` chains.

Walked with a list, not recursion: a chain is as long as the file makes it.
"""

from __future__ import annotations

from belvedere.description.urdf import Pose
from belvedere.errors import SourceLocation
from belvedere.world._model import SDFError
from belvedere.world._poses import compose

__all__ = ["Frame", "resolve_frames"]

Frame = tuple[Pose, str | None, SourceLocation | None]
"""A frame's pose, the frame it is relative to (None: the model's), where it was written."""

_MODEL_FRAMES = (None, "", "__model__")


def resolve_frames(frames: dict[str, Frame]) -> dict[str, Pose]:
    """Every frame's pose in the model frame; a cycle or an unknown frame is an error at the
    pose that names it."""
    done: dict[str, Pose] = {}
    for start in frames:
        chain: list[str] = []  # frames waiting for the one they are relative to
        name = start
        while name not in done:
            pose, rel, loc = frames[name]
            if rel in _MODEL_FRAMES:
                done[name] = pose
                break
            assert rel is not None
            if rel == name or rel in chain:
                cycle = [*chain[chain.index(rel) :], name] if rel in chain else [name]
                through = " -> ".join([*cycle, rel])
                msg = f"pose of {rel!r} is relative to itself through {through}"
                raise SDFError(msg, frames[rel][2])
            if rel not in frames:
                known = ", ".join(sorted(frames)) or "none"
                msg = f"pose of {name!r} is relative_to {rel!r}, which is not a frame here"
                raise SDFError(msg, loc, hint=f"frames of this model: {known}")
            chain.append(name)
            name = rel
        for waiting in reversed(chain):
            pose, rel, _ = frames[waiting]
            assert rel is not None
            done[waiting] = compose(done[rel], pose)
    return done
