"""The TF buffer's frame tree as text: tf2's ``allFramesAsString``, ``allFramesAsYAML`` and
``allFramesAsDot`` (for rospy's ``tf2_ros`` and ``tf``), and belvedere's indented tree."""

from __future__ import annotations

from belvedere.tf._cache import NS, StaticCache, TimeCache, seconds

__all__: list[str] = []


class _FrameListings:
    """The listings of :class:`~belvedere.tf.TFBuffer`'s frames (its frames, their caches and
    who sent each)."""

    _names: list[str]
    _ids: dict[str, int]
    _caches: list[TimeCache | StaticCache | None]
    _authority: dict[int, str]

    # --- listings --------------------------------------------------------------------------------
    def frame_strings(self) -> list[str]:
        """Every frame ever named, in order of appearance."""
        return self._names[1:]

    def frame_exists(self, frame: str) -> bool:
        return frame in self._ids

    def _parent_now(self, number: int) -> int | None:
        """The parent of the frame's latest transform (0 when it has none); None for a frame
        that never was a child."""
        cache = self._caches[number]
        if cache is None:
            return None
        got = cache.get(0)
        return 0 if isinstance(got, str) else got.parent

    def all_frames_as_string(self) -> str:
        lines = []
        for number in range(1, len(self._names)):
            parent = self._parent_now(number)
            if parent is not None:
                lines.append(
                    f"Frame {self._names[number]} exists with parent {self._names[parent]}.\n"
                )
        return "".join(lines)

    def _rate(self, cache: TimeCache | StaticCache) -> float:
        return len(cache) / max(seconds(cache.latest()) - seconds(cache.oldest()), 0.0001)

    def all_frames_as_yaml(self, current_time: float = 0.0) -> str:
        if len(self._names) == 1:
            return "{}"
        out: list[str] = []
        for number in range(1, len(self._names)):
            cache = self._caches[number]
            parent = self._parent_now(number)
            if cache is None or not parent:
                continue
            out.append(f"{self._names[number]}: \n")
            out.append(f"  parent: '{self._names[parent]}'\n")
            out.append(f"  broadcaster: '{self._authority.get(number, 'no recorded authority')}'\n")
            out.append(f"  rate: {self._rate(cache):.3f}\n")
            out.append(f"  most_recent_transform: {seconds(cache.latest()):.3f}\n")
            out.append(f"  oldest_transform: {seconds(cache.oldest()):.3f}\n")
            if current_time > 0:
                out.append(f"  transform_delay: {current_time - seconds(cache.latest()):.3f}\n")
            out.append(f"  buffer_length: {seconds(cache.latest() - cache.oldest()):.3f}\n")
        return "".join(out)

    def all_frames_as_dot(self, current_time: float = 0.0) -> str:
        """The tree in Graphviz's language, as tf's ``allFramesAsDot``."""
        out = ["digraph G {\n"]
        if len(self._names) == 1:
            out.append('"no tf data recieved"')
        for number in range(1, len(self._names)):
            cache = self._caches[number]
            parent = self._parent_now(number)
            if cache is None or not parent:
                continue
            authority = self._authority.get(number, "no recorded authority")
            latest = seconds(cache.latest())
            age = f"( {current_time - latest:.3f} sec old)" if current_time > 0 else ""
            out.append(
                f'"{self._names[parent]}" -> "{self._names[number]}"[label="'
                f"Broadcaster: {authority}\\n"
                f"Average rate: {self._rate(cache):.3f} Hz\\n"
                f"Most recent transform: {latest:.3f} {age}\\n"
                f"Buffer length: {seconds(cache.latest() - cache.oldest()):.3f} sec\\n"
                '"];\n'
            )
        legend = (
            ' subgraph cluster_legend { style=bold; color=black; label ="view_frames Result";\n'
        )
        recorded = f'"Recorded at time: {current_time:.3f}"[ shape=plaintext ] ;\n '
        for number in range(1, len(self._names)):
            parent = self._parent_now(number)
            if parent is None and current_time > 0:
                out.append("edge [style=invis];\n" + legend + recorded)
                out.append(f'}}->"{self._names[number]}";\n')
            elif parent == 0:
                out.append("edge [style=invis];\n" + legend)
                if current_time > 0:
                    out.append(recorded)
                out.append(f'}}->"{self._names[number]}";\n')
        out.append("}")
        return "".join(out)

    def tree(self, now_ns: int | None = None) -> str:
        """The frame tree as text (like view_frames): parent, rate and last update."""
        children: dict[int, list[int]] = {}
        for number in range(1, len(self._names)):
            parent = self._parent_now(number)
            if parent:
                children.setdefault(parent, []).append(number)
        lines: list[str] = []

        def walk(number: int, depth: int) -> None:
            cache = self._caches[number]
            detail = ""
            if isinstance(cache, StaticCache):
                detail = " [static]"
            elif cache is not None and len(cache):
                span = seconds(cache.latest() - cache.oldest())
                rate = (len(cache) - 1) / span if span > 0 else 0.0
                latest = cache.latest()
                age = f" , {((now_ns or latest) - latest) / NS:.3f} s ago" if now_ns else ""
                detail = f" [{rate:.1f} Hz, last {latest / NS:.3f} s{age}]"
            lines.append("  " * depth + self._names[number] + detail)
            for c in sorted(children.get(number, []), key=lambda n: self._names[n]):
                walk(c, depth + 1)

        roots = [
            n for n in range(1, len(self._names)) if not self._parent_now(n) and (n in children)
        ]
        for root in sorted(roots, key=lambda n: self._names[n]):
            walk(root, 0)
        return "\n".join(lines)
