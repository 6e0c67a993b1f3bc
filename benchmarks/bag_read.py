"""Reading speed: how fast ``open_bag(...).messages()`` hands out a bag's messages, against a
reference reader measured in the same run on the same file.

The bags are written here with belvedere's writers (the simulation's mix: odometry, TF, joint
states, model states, clock and laser scans), in each format and compression; the reference
for a ROS 1 bag is rosbags' reader (``rosbags.rosbag1.Reader``), for MCAP the ``mcap``
package's (``make_reader(...).iter_messages(log_time_order=True)``). Both read raw bytes, in
time order, every message; each number is the best of ``--repeat`` runs. A ratio above 1 is
faster than the reference. With ``--bag`` (e.g. /work/shared/data/slam/aces.bag) that file is
read too.

    python benchmarks/bag_read.py [--messages 100000] [--repeat 3] [--bag FILE]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

MIX = [
    (
        "/odom",
        "nav_msgs/Odometry",
        {"header": {"frame_id": "odom"}, "child_frame_id": "base_footprint"},
        4,
    ),
    ("/tf", "tf2_msgs/TFMessage", {"transforms": [{"header": {"frame_id": "odom"}}] * 2}, 4),
    (
        "/joint_states",
        "sensor_msgs/JointState",
        {"name": ["left", "right"], "position": [0.1, 0.2], "velocity": [1.0, 1.0]},
        4,
    ),
    ("/clock", "rosgraph_msgs/Clock", {}, 2),
    ("/scan", "sensor_msgs/LaserScan", {"ranges": [1.5] * 360, "intensities": [0.0] * 360}, 1),
]
"""The simulation's mix: (topic, type, content, messages per 15)."""


def write_mix(path: Path, messages: int, compression: str) -> None:
    """``messages`` messages of :data:`MIX`, one every millisecond."""
    from belvedere.bags import create_writer
    from belvedere.bags._model import encode
    from belvedere.msgs import message_from_data, types

    writer = create_writer(path, compression=compression)
    order: list[tuple[int, bytes]] = []
    for topic, kind, content, weight in MIX:
        msgtype = types().resolve(kind)
        conn = writer.add_connection(topic, msgtype, callerid="/gazebo", latching=False)
        data = encode(message_from_data(kind, content), writer.encoding)
        order += [(conn, data)] * weight
    for i in range(messages):
        conn, data = order[i % len(order)]
        writer.write(conn, 1_000_000_000 + i * 1_000_000, data)
    writer.close()


def ours(path: Path) -> int:
    from belvedere.bags import open_bag

    bag = open_bag(path)
    try:
        return sum(1 for _ in bag.messages())
    finally:
        bag.close()


def rosbags_reader(path: Path) -> int:
    from rosbags.rosbag1 import Reader

    with Reader(path) as reader:
        return sum(1 for _ in reader.messages())


def mcap_reader(path: Path) -> int:
    from mcap.reader import make_reader

    with path.open("rb") as f:
        return sum(1 for _ in make_reader(f).iter_messages(log_time_order=True))


def best(fn: Callable[[Path], int], path: Path, repeat: int) -> tuple[float, int]:
    """(messages per second, messages) of the fastest of ``repeat`` runs."""
    times = []
    count = 0
    for _ in range(repeat):
        started = time.perf_counter()
        count = fn(path)
        times.append(time.perf_counter() - started)
    return count / min(times), count


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--messages", type=int, default=100_000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--bag", type=Path, help="a bag of your own to read as well")
    args = parser.parse_args()
    import belvedere

    print(f"belvedere from {Path(belvedere.__file__).parent}")
    with tempfile.TemporaryDirectory() as tmp:
        files = [
            (Path(tmp) / f"mix_{c}.{ext}", c)
            for ext, cs in (("bag", ("none", "lz4", "bz2")), ("mcap", ("none", "lz4", "zstd")))
            for c in cs
        ]
        for path, compression in files:
            write_mix(path, args.messages, compression)
        if args.bag is not None:
            files.append((args.bag, "(as found)"))
        print(f"{'file':<22} {'belvedere':>12} {'reference':>12} {'ratio':>6}")
        for path, compression in files:
            reference = rosbags_reader if path.suffix == ".bag" else mcap_reader
            mine, n = best(ours, path, args.repeat)
            theirs, m = best(reference, path, args.repeat)
            assert n == m, f"{path.name}: {n} messages read, the reference read {m}"
            name = path.name if compression == "(as found)" else f"{path.suffix[1:]} {compression}"
            print(f"{name:<22} {mine:10.0f}/s {theirs:10.0f}/s {mine / theirs:6.2f}")


if __name__ == "__main__":
    main()
