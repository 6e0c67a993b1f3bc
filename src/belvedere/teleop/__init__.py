"""Keyboard teleoperation: teleop_twist_keyboard's layout and the course's mbot_teleop, read
from a real terminal in raw mode."""

from belvedere.teleop._layouts import LAYOUTS, Layout, MbotTeleop, Output, TurtleKeys, TwistKeyboard
from belvedere.teleop._terminal import raw_terminal, read_key, run_teleop

__all__ = [
    "LAYOUTS",
    "Layout",
    "MbotTeleop",
    "Output",
    "TurtleKeys",
    "TwistKeyboard",
    "raw_terminal",
    "read_key",
    "run_teleop",
]
