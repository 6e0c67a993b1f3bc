"""What a message carries besides its bytes (its stamp, type, node and, when latched, which
publication it is), and latching: each latched publication taken exactly once however it came.
"""

from __future__ import annotations

import struct
import weakref
from dataclasses import dataclass
from typing import Any, Final

from belvedere.graph._endpoints import Subscription

__all__ = ["LatchedOnce", "Sent"]

_STAMP: Final = struct.Struct("<cq")
"""A message's publication time, sent with it: kind (``s`` simulated, ``w`` wall) and ns.
After it come the message's type and its publisher's node (``type\nnode``): a subscriber
that wants another type drops the message unread and says so once (ROS 1 refuses such a
connection when it is made; Zenoh has no connections)."""


@dataclass(frozen=True, slots=True)
class Sent:
    """What a message carries besides its bytes (a Zenoh attachment)."""

    stamp: tuple[bool, int] | None = None
    """(simulated?, ns): the publishing graph's time when it was published."""
    type: str | None = None
    node: str | None = None
    """The publisher's node."""
    latch: tuple[str, int] | None = None
    """A latching publisher's message: (that publisher, the number of its publication). The
    same publication can come again: see :class:`LatchedOnce`."""


def _sender(text: str) -> tuple[str | None, str | None, tuple[str, int] | None]:
    """``type\nnode[\npublisher:number]``: what follows a message's stamp, and what a latched
    reply carries."""
    type_name, _, rest = text.partition("\n")
    node, _, tag = rest.partition("\n")
    who, _, number = tag.rpartition(":")
    latch = (who, int(number)) if who and number.isdigit() else None
    return type_name or None, node or None, latch


def _sent(attachment: Any) -> Sent:
    if attachment is None:
        return Sent()
    raw = attachment.to_bytes()
    if len(raw) < _STAMP.size:
        return Sent()
    kind, ns = _STAMP.unpack_from(raw)
    return Sent((kind == b"s", ns), *_sender(raw[_STAMP.size :].decode(errors="replace")))


class LatchedOnce:
    """The latched publications one receiver has had, so that it takes each exactly once
    however it came: published while it listened, replied to its question for latched
    messages, or sent again when its publisher first saw a subscriber elsewhere (as ROS 1
    sends the latched message on every new connection)."""

    def __init__(self) -> None:
        self._newest: dict[str, int] = {}
        """Each latching publisher's newest publication had."""

    def fresh(self, latch: tuple[str, int] | None) -> bool:
        """Whether a message (``latch``: see :attr:`Sent.latch`) is new to this receiver."""
        if latch is None:
            return True
        who, number = latch
        if self._newest.get(who, -1) >= number:
            return False
        self._newest[who] = number
        return True


class _LatchedSeen:
    """A :class:`LatchedOnce` for each subscription. Used on the executor's thread only."""

    def __init__(self) -> None:
        self._seen: weakref.WeakKeyDictionary[Subscription, LatchedOnce] = (
            weakref.WeakKeyDictionary()
        )

    def fresh(self, subscription: Subscription, latch: tuple[str, int] | None) -> bool:
        once = self._seen.get(subscription)
        if once is None:
            once = self._seen[subscription] = LatchedOnce()
        return once.fresh(latch)
