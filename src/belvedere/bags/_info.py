"""``rosbag info``'s summary of a bag, in its layout."""

from __future__ import annotations

import itertools
import time
from collections import defaultdict

from belvedere.bags._files import BagFile
from belvedere.bags._model import ros1_definition
from belvedere.msgs import short, types

__all__ = ["info_text"]

NS = 1_000_000_000


def _size(size: float) -> str:
    for suffix in ("KB", "MB", "GB", "TB", "PB", "EB", "ZB", "YB"):
        size /= 1024.0
        if size < 1024.0:
            return f"{size:.1f} {suffix}"
    return "-"


def _frequency(freq: float) -> str:
    for suffix in ("Hz", "kHz", "MHz", "GHz", "THz", "PHz", "EHz", "ZHz", "YHz"):
        if freq < 1000.0:
            return f"{freq:.1f} {suffix}"
        freq /= 1000.0
    return "-"


def _stamp(secs: float) -> str:
    frac = f"{secs - int(secs):.2f}"[1:]
    return time.strftime("%b %d %Y %H:%M:%S", time.localtime(secs)) + frac


def _duration(duration: float) -> str:
    secs = duration % 60
    mins = int(duration / 60)
    hours = int(mins / 60)
    if hours > 0:
        return f"{hours}hr {mins % 60}:{int(secs):02d}s ({int(duration)}s)"
    if mins > 0:
        return f"{mins}:{int(secs):02d}s ({int(duration)}s)"
    return f"{duration:.1f}s"


def _median(values: list[float]) -> float:
    ordered = sorted(values)
    n = len(ordered)
    if n % 2:
        return ordered[n // 2]
    return (ordered[n // 2 - 1] + ordered[n // 2]) / 2


def _md5(msgtype: str, given: str) -> str:
    if given:
        return given
    if msgtype in types().store.fielddefs:
        return ros1_definition(msgtype)[1]
    return "?"


def info_text(bag: BagFile, *, freq: bool = False, shown_path: str | None = None) -> str:
    """What ``rosbag info`` prints for ``bag`` (``freq``: with each topic's median rate)."""
    rows: list[tuple[str, str]] = [("path", shown_path or str(bag.path))]
    rows.append(("version", bag.version))
    total = sum(bag.counts.values())
    if not total:
        rows.append(("size", _size(bag.size)))
        return _layout(rows)
    start, end = bag.start_ns / NS, bag.end_ns / NS
    duration = end - start
    rows.append(("duration", _duration(duration)))
    rows.append(("start", f"{_stamp(start)} ({start:.2f})"))
    rows.append(("end", f"{_stamp(end)} ({end:.2f})"))
    rows.append(("size", _size(bag.size)))
    rows.append(("messages", str(total)))
    rows += _compression(bag, duration)
    connections = bag.connections
    type_rows: dict[str, str] = {}
    for conn in connections:
        name = short(conn.msgtype)
        type_rows.setdefault(name, _md5(conn.msgtype, conn.md5sum))
    by_topic: dict[str, list[int]] = defaultdict(list)
    topic_type: dict[str, str] = {}
    for conn in connections:
        by_topic[conn.topic].append(conn.id)
        topic_type.setdefault(conn.topic, short(conn.msgtype))
    counts = {t: sum(bag.counts.get(i, 0) for i in ids) for t, ids in by_topic.items()}
    rates = _rates(bag) if freq else {}
    topics = sorted(by_topic)
    topic_len = max(len(t) for t in topics)
    type_len = max(len(t) for t in type_rows)
    count_len = max(len(str(n)) for n in counts.values())
    freq_len = max((len(_frequency(f)) for f in rates.values()), default=0)
    for i, (name, md5) in enumerate(sorted(type_rows.items())):
        rows.append(("types" if i == 0 else "", f"{name:<{type_len}} [{md5}]"))
    for i, topic in enumerate(topics):
        n = counts[topic]
        text = f"{topic:<{topic_len}}   {n:>{count_len}} {'msgs' if n > 1 else 'msg '}"
        if topic in rates:
            text += f" @ {_frequency(rates[topic]):>{freq_len}}"
        else:
            text += f"   {'':>{freq_len}}"
        text += f" : {topic_type[topic]:<{type_len}}"
        if len(by_topic[topic]) > 1:
            text += f" ({len(by_topic[topic])} connections)"
        rows.append(("topics" if i == 0 else "", text))
    return _layout(rows)


def _compression(bag: BagFile, duration: float) -> list[tuple[str, str]]:
    chunks = bag.chunks()
    if not chunks:
        return [("compression", "none")]
    counts: dict[str, int] = defaultdict(int)
    plain: dict[str, int] = defaultdict(int)
    packed: dict[str, int] = defaultdict(int)
    for c in chunks:
        counts[c.compression] += 1
        plain[c.compression] += c.uncompressed
        packed[c.compression] += c.compressed
    parts = []
    for count, name in sorted(((v, k) for k, v in counts.items()), reverse=True):
        if name != "none":
            fraction = 100.0 * packed[name] / plain[name] if plain[name] else 0.0
            parts.append(f"{name} [{count}/{len(chunks)} chunks; {fraction:.2f}%]")
        else:
            parts.append(f"{name} [{count}/{len(chunks)} chunks]")
    rows = [("compression", ", ".join(parts))]
    if any(name != "none" for name in counts):
        total_plain = sum(c.uncompressed for c in chunks)
        total_packed = sum(c.compressed for c in chunks)
        a, b = _size(total_plain), _size(total_packed)
        width = max(len(a), len(b))
        if duration > 0:
            ra, rb = _size(total_plain / duration), _size(total_packed / duration)
            rate_width = max(len(ra), len(rb))
            percent = 100.0 * total_packed / total_plain if total_plain else 0.0
            rows.append(("uncompressed", f"{a:>{width}} @ {ra:>{rate_width}}/s"))
            rows.append(("compressed", f"{b:>{width}} @ {rb:>{rate_width}}/s ({percent:.2f}%)"))
        else:
            rows.append(("uncompressed", f"{a:>{width}}"))
            rows.append(("compressed", f"{b:>{width}}"))
    return rows


def _rates(bag: BagFile) -> dict[str, float]:
    stamps: dict[str, list[int]] = defaultdict(list)
    for m in bag.messages():
        stamps[m.connection.topic].append(m.stamp_ns)
    rates = {}
    for topic, times in stamps.items():
        if len(times) > 1:
            times.sort()
            period = _median([(b - a) / NS for a, b in itertools.pairwise(times)])
            if period > 0:
                rates[topic] = 1.0 / period
    return rates


def _layout(rows: list[tuple[str, str]]) -> str:
    width = max(len(name) for name, _ in rows) + 1
    lines = [f"{(name + ':') if name else '':<{width}} {value}" for name, value in rows]
    return "\n".join(lines).rstrip()
