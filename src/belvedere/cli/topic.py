"""``belvedere topic list|echo|pub|hz|info|type|bw`` — rostopic, with no roscore."""

from __future__ import annotations

import argparse
import itertools
import statistics
import sys
import threading
import time
from collections import deque
from typing import Any

from belvedere.cli._tool import action_parsers, graph_address
from belvedere.errors import BelvedereError
from belvedere.graph import NS, GraphInfo, did_you_mean, resolve_name
from belvedere.msgs import message_from_args, message_to_yaml, short, types
from belvedere.runtime import Tool, open_tool, wait_for, wait_for_messages

__all__ = ["add_parser", "run"]


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser("topic", parents=[common], help="list, echo, publish, measure topics")
    verb = action_parsers(p, common)

    v = verb("list", "topics with publishers or subscribers (-v: rostopic list -v's listing)")
    v.add_argument("namespace", nargs="?", help="only this topic or the topics under it")
    v.add_argument("-t", "--types", action="store_true", help="show each topic's type")
    v.add_argument("-p", dest="publishers_only", action="store_true", help="published only")
    v.add_argument("-s", dest="subscribers_only", action="store_true", help="subscribed only")
    v = verb("echo", "print messages")
    v.add_argument("topic")
    v.add_argument("-n", dest="count", type=int, help="stop after COUNT messages")
    v.add_argument("--noarr", action="store_true", help="show arrays as their type and length")
    v.add_argument("--offset", action="store_true", help="show header stamps as offsets from now")
    v.add_argument("--timeout", type=float, default=None, help="give up after SECONDS")
    v = verb("pub", "publish a message")
    v.add_argument("topic")
    v.add_argument("type")
    v.add_argument("values", nargs="*", help="YAML: one mapping, or one value per field")
    v.add_argument("-r", dest="rate", type=float, help="publish at RATE Hz until stopped")
    v.add_argument("-1", "--once", action="store_true", help="publish once, then exit")
    v.add_argument("-l", "--latch", action="store_true", help="latch (the default without -r)")
    v.add_argument("--count", type=int, help="with -r: stop after COUNT messages")
    v = verb("hz", "message rate")
    v.add_argument("topic")
    v.add_argument("-w", dest="window", type=int, default=1000, help="window (messages)")
    v.add_argument("--duration", type=float, help="stop after SECONDS")
    v = verb("bw", "bandwidth")
    v.add_argument("topic")
    v.add_argument("--duration", type=float, help="stop after SECONDS")
    v = verb("info", "type, publishers and subscribers")
    v.add_argument("topic")
    v = verb("type", "the topic's message type")
    v.add_argument("topic")
    verb("find", "the topics of a message type").add_argument("type")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    tool = open_tool(graph_address(args), "topic")
    try:
        action = {
            "list": _list,
            "echo": _echo,
            "pub": _pub,
            "hz": _hz,
            "bw": _bw,
            "info": _info,
            "type": _type,
            "find": _find,
        }[args.action]
        tool.graph.start(rtf=None)
        return action(tool, args)
    except KeyboardInterrupt:
        if tool.ended_by is None:
            raise
        return 0  # node kill: rostopic's clean end
    finally:
        tool.close()


def _name(topic: str) -> str:
    return resolve_name(topic)


def _topic_type(tool: Tool, topic: str, timeout: float | None) -> str:
    """The type of a topic someone publishes (waiting up to ``timeout``; None: forever)."""
    found: list[str] = []
    known: set[str] = set()

    def look() -> bool:
        info = tool.info(timeout=0.3)
        typ = info.topic_type(topic)
        if typ:
            found.append(typ)
        known.clear()
        known.update(_topics(info))
        return bool(found)

    if timeout is None:
        if not wait_for(look, 1.0, step=0.2):
            close = did_you_mean(topic, known)
            waiting = f"waiting for {topic} to appear (Ctrl-C to stop)"
            sys.stderr.write(f"{waiting}; {close}\n" if close else f"{waiting}…\n")
            wait_for(look, float("inf"), step=0.2)
        return found[0]
    if not wait_for(look, timeout, step=0.2):
        msg = f"no node publishes or subscribes to {topic} (waited {timeout:g} s)"
        hint = did_you_mean(topic, known) or "check the name with 'belvedere topic list'"
        raise BelvedereError(msg, hint=hint)
    return found[0]


def _topics(info: GraphInfo) -> set[str]:
    """Every topic someone publishes or subscribes to."""
    return set(info.publishers) | set(info.subscribers)


def _unknown(topic: str, info: GraphInfo) -> BelvedereError:
    msg = f"unknown topic {topic}: no node publishes or subscribes to it"
    return BelvedereError(msg, hint=did_you_mean(topic, _topics(info)))


def _list(tool: Tool, args: argparse.Namespace) -> int:
    """rostopic list: the topics' names (with ``-t`` their types), or with ``-v`` the
    published and the subscribed topics, each with its type and how many nodes."""
    if args.publishers_only and args.subscribers_only:
        msg = "cannot specify both subscribers- and publishers-only"
        raise BelvedereError(msg)
    info = tool.info()
    pubs, subs = _within(info.publishers, args.namespace), _within(info.subscribers, args.namespace)
    if args.verbose > 0:
        out: list[str] = []
        if not args.subscribers_only:
            out += ["", "Published topics:", *_counted(pubs, "publisher")]
        if not args.publishers_only:
            out += ["", "Subscribed topics:", *_counted(subs, "subscriber")]
        sys.stdout.write("\n".join([*out, ""]) + "\n")
        return 0
    if args.publishers_only:
        names = sorted(pubs)
    elif args.subscribers_only:
        names = sorted(subs)
    else:
        names = sorted(set(pubs) | set(subs))
    for name in names:
        if args.types:
            sys.stdout.write(f"{name} [{short(info.topic_type(name) or '?')}]\n")
        else:
            sys.stdout.write(name + "\n")
    return 0


def _within(
    table: dict[str, set[tuple[str, str]]], namespace: str | None
) -> dict[str, set[tuple[str, str]]]:
    """The entries of ``table`` for the topic ``namespace`` or those under it (all: None)."""
    if not namespace:
        return table
    name = _name(namespace)
    under = name.rstrip("/") + "/"
    return {t: e for t, e in table.items() if t == name or t.startswith(under)}


def _counted(table: dict[str, set[tuple[str, str]]], what: str) -> list[str]:
    """`` * /topic [type] N publishers`` lines, by topic (a node counts once per topic)."""
    rows = []
    for topic, entries in sorted(table.items()):
        count = len({node for _, node in entries})
        noun = what if count == 1 else what + "s"
        rows.append(f" * {topic} [{short(min(entries)[0])}] {count} {noun}")
    return rows


def _echo(tool: Tool, args: argparse.Namespace) -> int:
    topic = _name(args.topic)
    msg_type = _topic_type(tool, topic, args.timeout)
    printed = threading.Semaphore(0)
    count = [0]
    limit = args.count

    def show(msg: Any) -> None:
        if limit is not None and count[0] >= limit:
            return
        count[0] += 1
        text = message_to_yaml(msg, noarr=args.noarr)
        if args.offset and hasattr(msg, "header"):
            stamp = msg.header.stamp
            # rostopic's offset is from the node's now: the simulation's under /use_sim_time
            offset = tool.graph.now_ns() / NS - (stamp.sec + stamp.nanosec * 1e-9)
            text = f"offset: {offset:.6f}\n" + text
        sys.stdout.write(text + "\n---\n")
        sys.stdout.flush()
        printed.release()

    if args.offset:
        tool.wait_for_clock()  # offsets from the graph's now: not from 0 before /clock
    tool.node.subscribe(topic, msg_type, show, queue_size=100)
    timeout = args.timeout
    nothing = f"no message on {topic} within {timeout or 0:g} s"
    wait_for_messages(
        printed,
        limit=limit,
        timeout=timeout,
        nothing=BelvedereError(nothing, hint="is its publisher running?"),
    )
    return 0


def _pub(tool: Tool, args: argparse.Namespace) -> int:
    topic = _name(args.topic)
    msg_type = types().resolve(args.type)
    seq = [0]

    def build() -> Any:
        msg = message_from_args(msg_type, args.values, clock=tool.graph.clock_stamp, seq=seq[0])
        seq[0] += 1
        return msg

    tool.wait_for_clock()  # stamps of "now" (and auto headers) in the graph's time
    first = build()  # bad YAML fails here, before anything is advertised
    latch = args.latch or args.rate is None
    pub = tool.node.publisher(topic, msg_type, latch=latch)
    # Give subscribers in other processes a moment to see us (rostopic waits too).
    wait_for(lambda: pub.topic.remote, 1.0)
    if args.rate is None:
        pub.publish(first)
        if args.once:
            wait_for(lambda: False, 1.0)  # let the message leave before closing
            return 0
        sys.stderr.write(f"publishing and latching {short(msg_type)} on {topic} (Ctrl-C to stop)\n")
        while True:
            time.sleep(3600)
    if args.rate <= 0:
        msg = f"-r RATE must be positive, got {args.rate!r}"
        raise BelvedereError(msg)
    period = 1.0 / args.rate
    sent = 0
    next_at = time.monotonic()
    msg = first
    while args.count is None or sent < args.count:
        pub.publish(msg)
        sent += 1
        msg = build()
        next_at += period
        time.sleep(max(0.0, next_at - time.monotonic()))
    wait_for(lambda: False, 0.3)
    return 0


def _hz(tool: Tool, args: argparse.Namespace) -> int:
    topic = _name(args.topic)
    msg_type = _topic_type(tool, topic, args.duration)
    stamps: deque[float] = deque(maxlen=args.window)
    lock = threading.Lock()

    def on_msg(_: Any) -> None:
        with lock:
            stamps.append(time.monotonic())

    tool.node.subscribe(topic, msg_type, on_msg, queue_size=1000)
    start = time.monotonic()
    while args.duration is None or time.monotonic() - start < args.duration:
        time.sleep(1.0)
        with lock:
            times = list(stamps)
        if len(times) < 2:
            sys.stdout.write("no new messages\n")
            continue
        gaps = [b - a for a, b in itertools.pairwise(times)]
        mean = statistics.fmean(gaps)
        sys.stdout.write(
            f"average rate: {1.0 / mean:.3f}\n\tmin: {min(gaps):.3f}s max: {max(gaps):.3f}s "
            f"std dev: {statistics.pstdev(gaps):.5f}s window: {len(times)}\n"
        )
        sys.stdout.flush()
    return 0


def _bw(tool: Tool, args: argparse.Namespace) -> int:
    topic = _name(args.topic)
    msg_type = _topic_type(tool, topic, args.duration)
    sizes: deque[tuple[float, int]] = deque(maxlen=100)

    def on_msg(msg: Any) -> None:
        sizes.append((time.monotonic(), len(types().serialize(msg))))

    tool.node.subscribe(topic, msg_type, on_msg, queue_size=1000)
    start = time.monotonic()
    while args.duration is None or time.monotonic() - start < args.duration:
        time.sleep(1.0)
        window = list(sizes)
        if len(window) < 2:
            sys.stdout.write("no new messages\n")
            continue
        span = window[-1][0] - window[0][0] or 1e-9
        total = sum(s for _, s in window)
        sys.stdout.write(
            f"average: {total / span:.2f}B/s\n\tmean: {total / len(window):.2f}B "
            f"min: {min(s for _, s in window)}B max: {max(s for _, s in window)}B "
            f"window: {len(window)}\n"
        )
        sys.stdout.flush()
    return 0


def _info(tool: Tool, args: argparse.Namespace) -> int:
    topic = _name(args.topic)
    info = tool.info()
    typ = info.topic_type(topic)
    if typ is None:
        raise _unknown(topic, info)
    out = [f"Type: {short(typ)}", "", "Publishers: "]
    out += [f" * {node}" for _, node in sorted(info.publishers.get(topic, ()))] or [" None"]
    out += ["", "Subscribers: "]
    out += [f" * {node}" for _, node in sorted(info.subscribers.get(topic, ()))] or [" None"]
    sys.stdout.write("\n".join(out) + "\n")
    return 0


def _type(tool: Tool, args: argparse.Namespace) -> int:
    topic = _name(args.topic)
    info = tool.info()
    typ = info.topic_type(topic)
    if typ is None:
        raise _unknown(topic, info)
    sys.stdout.write(short(typ) + "\n")
    return 0


def _find(tool: Tool, args: argparse.Namespace) -> int:
    """rostopic find: the topics published or subscribed with messages of the type."""
    wanted = types().resolve(args.type)
    info = tool.info()
    found = {
        topic
        for table in (info.publishers, info.subscribers)
        for topic, entries in table.items()
        if any(typ == wanted for typ, _ in entries)
    }
    sys.stdout.write("\n".join(sorted(found)) + "\n")  # none: one empty line, as rostopic
    return 0
