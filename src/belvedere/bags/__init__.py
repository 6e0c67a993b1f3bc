"""Bags: recording a graph's messages to files and playing them back, as ``rosbag`` does.

Two formats, chosen by the file's name: ``.bag`` is a ROS 1 bag (format 2.0; its
connections carry ROS 1's message definitions, MD5 sums, ``callerid`` and ``latching`` as
rosbag writes them), readable by ROS 1's rosbag; ``.mcap`` is MCAP with the ros2 profile
(CDR, as belvedere's transport carries messages; see :mod:`belvedere.bags._mcap`), readable
by Foxglove and rosbags. Both are written a chunk at least every second, so a recording
killed outright loses at most its last second, and :func:`reindex` repairs it.

Bags come from the internet, so reading trusts nothing a file declares
(:mod:`belvedere.bags._input`): a FIFO, a device or a directory is refused without being
read; every length and offset is checked against the file before it is used; every chunk
is inflated to at most the size it declares (a decompression bomb stops there, see
:func:`belvedere.bounded.inflate`). A damaged header, index or summary is one error naming
the file and the place (``x.bag: offset 4117: …``); a damaged chunk is one warning (the
first; the others are counted) and the rest of the bag still reads; ``reindex`` keeps what
comes before the first damage and leaves the original as it was.

- :func:`open_bag`, :func:`info_text`: read a bag; ``rosbag info``'s summary.
- :class:`Recorder` with :class:`TapRecording` (messages of other processes, as the
  transport receives them) or :class:`GraphRecording` (subscriptions in this process):
  ``rosbag record``.
- :class:`Player`: ``rosbag play`` on a graph, in the graph's time (``--clock``: the bag's).
- :func:`parse_record_args`, :func:`parse_play_args`: rosbag's command lines.
"""

from belvedere.bags._files import (
    BagFile,
    BagWriter,
    backup_path,
    create_writer,
    merged_messages,
    open_bag,
    reindex,
)
from belvedere.bags._info import info_text
from belvedere.bags._model import BagError, BagMessage, Connection, Decoder
from belvedere.bags._options import (
    PlayOptions,
    RecordOptions,
    add_play_options,
    add_record_options,
    bag_name,
    parse_play_args,
    parse_record_args,
    play_options,
    record_options,
)
from belvedere.bags._play import Player, PlayProgress
from belvedere.bags._progress import ProgressBar, wants_progress
from belvedere.bags._record import GraphRecording, Recorder, Sample, TapRecording

__all__ = [
    "BagError",
    "BagFile",
    "BagMessage",
    "BagWriter",
    "Connection",
    "Decoder",
    "GraphRecording",
    "PlayOptions",
    "PlayProgress",
    "Player",
    "ProgressBar",
    "RecordOptions",
    "Recorder",
    "Sample",
    "TapRecording",
    "add_play_options",
    "add_record_options",
    "backup_path",
    "bag_name",
    "create_writer",
    "info_text",
    "merged_messages",
    "open_bag",
    "parse_play_args",
    "parse_record_args",
    "play_options",
    "record_options",
    "reindex",
    "wants_progress",
]
