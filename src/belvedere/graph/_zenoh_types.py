"""Types over the graph: a process tells the others the definition of a type it knows, so
that ``topic echo``, ``bag record`` or the Foxglove bridge in a terminal without the user's
package can read a topic of a type only the publisher's package defines (ROS 1's
subscribers have it from the publisher's connection header, which carries the full text).

Each process answers on the key ``y/<type>`` (JSON: genmsg's full text and MD5 sum of a
message, of each half of a service); a process that meets a type it does not know asks
there, through the type registry, before calling it unknown. An answer is checked as a
bag's definition is (its size, genmsg's rules, the MD5 sum, no clash with a type known
here) before the type is learnt from it.
"""

from __future__ import annotations

import json
import logging
import re
import time
from typing import Any, Final

import zenoh

from belvedere.bounded import DEFINITION_BYTES
from belvedere.errors import BelvedereError
from belvedere.graph._zenoh_session import _Peer, decode_key, encode_key
from belvedere.msgs import learn_full_text, learn_service_text, ros1_text, types

__all__: list[str] = []

logger = logging.getLogger("belvedere.graph")

ASK_TIMEOUT: Final = 2.0
"""Seconds to wait for the processes' answers (a loaded machine answers in milliseconds)."""
ASK_AGAIN: Final = 5.0
"""Seconds before a type nobody knew is asked for again (a process asking each message
about a type nobody has would otherwise wait ASK_TIMEOUT each time)."""
ANSWER_BYTES: Final = 2 * DEFINITION_BYTES + 4096
"""An answer's size: two full texts (a service's halves) and the JSON around them."""
_MD5: Final = re.compile(r"[0-9a-f]{32}\Z")


class _TypeService(_Peer):
    """The transport's answers about the types this process knows, and its questions."""

    _unanswered: dict[str, float]
    """Store name → when it may be asked for again."""
    _closed: bool

    def _on_type_query(self, query: Any) -> None:
        name = decode_key(str(query.key_expr).removeprefix(self._key("y/")))
        try:
            answer = _describe(name)
        except (BelvedereError, KeyError, ValueError):
            answer = None  # not a type this process can describe: others may
        if answer is not None:
            query.reply(query.key_expr, json.dumps(answer).encode())

    def ask_type(self, name: str) -> bool:
        """Ask the other processes for type ``name`` (a store name: ``pkg/msg/Type``, or a
        service ``pkg/srv/Name``); whether it is known now. An answer that does not check
        out is an error saying why (when no good one came)."""
        now = time.monotonic()
        if self._closed or self._unanswered.get(name, 0.0) > now:
            return False
        try:
            replies = self.session.get(
                self._key("y/", encode_key(name)),
                timeout=ASK_TIMEOUT,
                target=zenoh.QueryTarget.ALL,
            )
        except zenoh.ZError:
            return False  # the session is closing
        problem: BelvedereError | None = None
        for reply in replies:
            if reply.ok is None:
                continue
            where = f"the graph's answer about {name} ({_replier(reply)})"
            try:
                _learn(name, reply.ok.payload.to_bytes(), where)
            except BelvedereError as err:
                problem = err
                continue
            logger.debug("learnt %s from %s", name, where)
            return True
        self._unanswered[name] = time.monotonic() + ASK_AGAIN
        if problem is not None:
            raise problem
        return False


def _describe(name: str) -> dict[str, Any] | None:
    """This process's answer about ``name``: None for a type it does not know."""
    registry = types()
    if "/srv/" in name:
        if name not in registry.services:
            return None
        halves = {}
        for half in ("Request", "Response"):
            described = ros1_text(f"{name}_{half}")
            halves[half] = {"definition": described.full_text, "md5sum": described.md5sum}
        return {"type": name, **halves}
    if name not in registry.store.fielddefs:
        return None
    described = ros1_text(name)
    return {"type": name, "definition": described.full_text, "md5sum": described.md5sum}


def _replier(reply: Any) -> str:
    replier = getattr(reply, "replier_id", None)
    return f"process {replier}" if replier is not None else "another process"


def _learn(name: str, payload: bytes, where: str) -> None:
    """Learn ``name`` from an answer, checked; a :class:`BelvedereError` says what is wrong."""
    if len(payload) > ANSWER_BYTES:
        msg = f"{where}: {len(payload)} bytes, past the {ANSWER_BYTES} an answer may hold"
        raise BelvedereError(msg)
    try:
        answer = json.loads(payload)
        if not isinstance(answer, dict) or answer.get("type") != name:
            msg = "it is not about that type"
            raise ValueError(msg)
        if "/srv/" in name:
            halves = {half: _text_and_md5(answer[half]) for half in ("Request", "Response")}
        else:
            text, md5sum = _text_and_md5(answer)
    except (ValueError, KeyError, TypeError) as err:
        msg = f"{where}: not a type's definition as belvedere answers one ({err})"
        raise BelvedereError(msg) from None
    if "/srv/" in name:
        learn_service_text(name, halves, where)
    else:
        learn_full_text(text, name, md5sum, where)


def _text_and_md5(part: Any) -> tuple[str, str]:
    text, md5sum = part["definition"], part["md5sum"]
    if not isinstance(text, str) or not isinstance(md5sum, str) or not _MD5.match(md5sum):
        msg = "a definition must be a text with an MD5 sum of 32 hexadecimal digits"
        raise ValueError(msg)
    return text, md5sum
