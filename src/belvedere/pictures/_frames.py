"""The TF tree as view_frames and rqt_tf_tree draw it: /tf and /tf_static listened to, each
edge with its broadcaster, average rate, most recent transform and buffer length
(tf2's ``allFramesAsDot``)."""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

from belvedere.graph import NS, Node
from belvedere.tf import TFBuffer

__all__ = ["FramesWatch", "Publishers"]

Publishers = Callable[[str], set[str]]
"""The nodes publishing a topic on the graph (asked off the executor: it may wait)."""

LOOK_S = 1.0
"""How often the topics' publishers are asked again, as broadcasters come and go."""
NO_AUTHORITY = "no recorded authority"


class FramesWatch:
    """Fills a TF buffer from ``node``'s subscriptions to /tf and /tf_static. Belvedere's
    messages carry no caller id, so an edge's broadcaster is the node publishing its topic
    (all of them, comma separated, when several do)."""

    def __init__(self, node: Node, publishers: Publishers) -> None:
        self.node = node
        self.buffer = TFBuffer()
        self._publishers = publishers
        self._who: dict[str, str] = {}
        self._stop = threading.Event()
        for topic, static in (("/tf", False), ("/tf_static", True)):
            node.subscribe(topic, "tf2_msgs/TFMessage", self._taker(topic, static), queue_size=100)
        self._look()
        threading.Thread(target=self._keep_looking, name="belvedere-frames", daemon=True).start()

    def _taker(self, topic: str, static: bool) -> Callable[[Any], None]:
        def take(msg: Any) -> None:
            who = self._who.get(topic, NO_AUTHORITY)
            self.buffer.set_message(msg, static=static, authority=who)

        return take

    def _look(self) -> None:
        for topic in ("/tf", "/tf_static"):
            found = sorted(self._publishers(topic) - {self.node.full_name})
            self._who[topic] = ", ".join(found) if found else NO_AUTHORITY

    def _keep_looking(self) -> None:
        while not self._stop.wait(LOOK_S):
            self._look()

    def dot(self) -> str:
        """The tree in Graphviz's language, recorded at the graph's time now."""
        return self.buffer.all_frames_as_dot(self.node.graph.now_ns() / NS)

    def frames(self) -> list[str]:
        return self.buffer.frame_strings()

    def close(self) -> None:
        self._stop.set()
