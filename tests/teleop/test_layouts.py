"""The key layouts: teleop_twist_keyboard's and the course's mbot_teleop."""

from __future__ import annotations

import pytest

from belvedere.teleop import MbotTeleop, TwistKeyboard


def test_twist_keyboard_directions_scales_and_stop() -> None:
    layout = TwistKeyboard()
    assert layout.key("i").twist == (0.5, 0.0, 0.0, 0.0)
    assert layout.key("u").twist == (0.5, 0.0, 0.0, 1.0)
    assert layout.key("m").twist == (-0.5, 0.0, 0.0, -1.0)
    assert layout.key("J").twist == (0.0, 0.5, 0.0, 0.0)  # Shift: holonomic
    assert layout.key(">").twist == (-0.5, -0.5, 0.0, 0.0)
    assert layout.key("t").twist == (0.0, 0.0, 0.5, 0.0)
    out = layout.key("q")  # scales keep the direction
    assert out.twist == pytest.approx((0.0, 0.0, 0.55, 0.0))
    assert out.text == "currently:\tspeed 0.55\tturn 1.1 "
    layout.key("w")
    layout.key("c")
    assert (layout.speed, layout.turn) == pytest.approx((0.605, 0.99))
    assert layout.key("k").twist == (0.0, 0.0, 0.0, 0.0)
    assert layout.key("?").twist == (0.0, 0.0, 0.0, 0.0)
    assert layout.key("\x03").quit


def test_twist_keyboard_reprints_help_every_15_speed_changes() -> None:
    layout = TwistKeyboard()
    texts = [layout.key("e").text or "" for _ in range(15)]
    assert all(layout.help not in t for t in texts[:14])
    assert texts[14].startswith(layout.help)


def test_twist_keyboard_key_timeout_stops_once() -> None:
    layout = TwistKeyboard(key_timeout=0.5)
    assert layout.poll == 0.5
    layout.key("i")
    assert layout.idle().twist == (0.0, 0.0, 0.0, 0.0)
    assert layout.idle().twist is None  # already stopped: nothing to publish
    assert TwistKeyboard().poll is None


def test_mbot_ramps_and_stops_smoothly() -> None:
    layout = MbotTeleop()
    assert layout.poll == 0.1
    speeds = [layout.key("i").twist]
    speeds += [layout.idle().twist for _ in range(9)]
    # 0.02 m/s per 0.1 s towards 0.2, until the 5th quiet poll, then back down
    linear = [t[0] for t in speeds if t is not None]
    assert linear == pytest.approx([0.02, 0.04, 0.06, 0.08, 0.1, 0.08, 0.06, 0.04, 0.02, 0.0])
    out = layout.key("j")
    assert out.twist == pytest.approx((0.0, 0.0, 0.0, 0.1))
    assert layout.key(" ").twist == (0.0, 0.0, 0.0, 0.0)  # space: at once
    assert layout.key("J").twist == (0.0, 0.0, 0.0, 0.0)  # no holonomic moves here
    assert layout.key("\x03").quit
