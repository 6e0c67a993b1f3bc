"""Every command of docs/tutorial.md and of the README's quick start, run as a user types it
(from a copy of the clone's layout, ``ROS_PACKAGE_PATH=examples``), with its output compared
where the page shows it. A command that runs until Ctrl-C is started, its viewer's page
fetched, then interrupted; the commands typed in a second terminal run beside it.

The table below says how each command is run: a command the pages gain must be added to it
(``test_every_command_of_the_pages_is_run`` fails naming it).
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import threading
import time
import urllib.request
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from tests.conftest import EXAMPLES
from tests.waiting import wait_until

ROOT = Path(__file__).resolve().parents[1]
TUTORIAL = ROOT / "docs" / "tutorial.md"
README = ROOT / "README.md"
START_S = 120.0
"""How long a long-running command may take to serve its viewer (a physics launch, loaded)."""
URL = re.compile(r"http://127\.0\.0\.1:\d+[^\s]*")


def page_commands(path: Path) -> list[str]:
    """The commands of a page's ``sh`` blocks: continuation lines joined, comments dropped."""
    text = path.read_text()
    if path == README:
        text = text[text.index("## Quick start") : text.index("## How it works")]
    return [c for block in re.findall(r"```sh\n(.*?)```", text, re.S) for c in _commands(block)]


def _commands(block: str) -> list[str]:
    """A ``sh`` block's commands (continuation lines joined, comments dropped), normalised."""
    lines = block.replace("\\\n", " ").splitlines()
    return [_normal(line) for line in lines if shlex.split(line, comments=True)]


def _normal(command: str) -> str:
    return " ".join(shlex.quote(w) for w in shlex.split(command, comments=True))


# --- how each command is run ---------------------------------------------------------------------
SETUP = {
    ". .venv/bin/activate",
    "export ROS_PACKAGE_PATH=$PWD/examples",
}
"""The environment every test gives its commands (this interpreter, the examples' path)."""
ELSEWHERE = {
    "belvedere teleop": "needs a terminal: tests/teleop drive it through a pseudo-terminal",
    "belvedere run mbot_teleop mbot_teleop.py": "needs a terminal: tests/teleop run it",
    "BELVEDERE_DOCS_SCREENSHOTS=docs/images python -m pytest -m browser tests/viewer": (
        "the browser tests themselves"
    ),
}


@dataclass
class Section:
    """A long-running command and what is typed beside it while it runs."""

    serve: list[str]
    beside: list[str] = field(default_factory=list)
    """Commands that end by themselves (run to the end, exit 0) or, listed in ``running``,
    that run until interrupted."""
    running: set[str] = field(default_factory=set)
    expect: dict[str, list[str]] = field(default_factory=dict)
    """Lines a command's output must contain, as the page shows them."""
    one_by_one: bool = False
    """The long-running commands are alternatives: each runs alone, then is interrupted."""


MBOT = "examples/mbot_description/urdf/xacro/gazebo/mbot_gazebo.xacro"
PUB_CIRCLE = (
    "belvedere topic pub -r 10 /cmd_vel geometry_msgs/Twist "
    "'{linear: {x: 0.2, y: 0, z: 0}, angular: {x: 0, y: 0, z: 0.5}}'"
)
PUB_README = (
    "belvedere topic pub -r 10 /cmd_vel geometry_msgs/Twist '{linear: {x: 0.2}, angular: {z: 0.5}}'"
)
MARM_POINT = (
    "belvedere topic pub -1 /marm/arm_controller/command trajectory_msgs/JointTrajectory "
    "'{joint_names: [joint1, joint2, joint3, joint4, joint5, joint6], points: [{positions: "
    "[0.5, 0.3, 0.3, 0, 0, 0], time_from_start: {secs: 2}}]}'"
)
SECTIONS: dict[str, Section] = {
    "display": Section([f"belvedere display {MBOT}"]),
    "display launches": Section(
        [
            "belvedere launch mbot_description display_mbot_base_urdf.launch",
            "belvedere launch mbot_description display_mbot_gazebo_xacro.launch",
        ],
        one_by_one=True,
    ),
    "arbotix launch": Section(
        ["belvedere launch mbot_description arbotix_mbot_with_camera_xacro.launch"],
        [PUB_CIRCLE],
        running={PUB_CIRCLE},
    ),
    "arbotix sim": Section(
        [f"belvedere sim {MBOT} --config examples/mbot_description/config/fake_mbot_arbotix.yaml"],
        [PUB_README],
        running={PUB_README},
    ),
    "rbx1": Section(
        ["belvedere launch rbx1_bringup fake_turtlebot.launch", "belvedere run rviz rviz"]
    ),
    "rbx1 nav": Section(
        [
            "belvedere launch rbx1_bringup fake_turtlebot.launch",
            "belvedere launch rbx1_nav fake_move_base_blank_map.launch",
            "belvedere run rviz rviz",
        ]
    ),
    "marm": Section(
        ["belvedere launch marm_description marm_gazebo_control.launch"],
        [
            "belvedere service call /marm/controller_manager/list_controllers",
            MARM_POINT,
            "belvedere topic echo -n 1 /marm/joint_states",
        ],
        expect={"belvedere topic echo -n 1 /marm/joint_states": ["name:", "position:"]},
    ),
    "gazebo": Section(
        [
            "belvedere launch mbot_gazebo view_mbot_gazebo_empty_world.launch",
            f"belvedere sim {MBOT} --engine physics",
            "belvedere launch mbot_gazebo view_mbot_gazebo_play_ground.launch",
            "belvedere launch gazebo_ros empty_world.launch world_name:=my.world",
            "belvedere launch mbot_gazebo view_mbot_with_camera_gazebo.launch",
            "belvedere launch mbot_gazebo view_mbot_with_kinect_gazebo.launch",
            "belvedere launch mbot_gazebo view_mbot_with_laser_gazebo.launch",
        ],
        one_by_one=True,
    ),
    "readme physics": Section(
        [
            "belvedere sim examples/mbot_description/urdf/xacro/gazebo/"
            "mbot_with_laser_gazebo.xacro --engine physics --world "
            "examples/mbot_gazebo/worlds/playground.world",
            "belvedere launch --package-path examples mbot_gazebo "
            "view_mbot_with_laser_gazebo.launch",
        ],
        one_by_one=True,
    ),
    "gmapping": Section(
        ["belvedere launch mbot_navigation gmapping_demo.launch"],
        [
            "belvedere run map_server map_saver -f cloister",
            "belvedere map show cloister.yaml",
        ],
    ),
    "navigation": Section(
        [
            "belvedere launch mbot_gazebo mbot_laser_nav_gazebo.launch",
            "belvedere launch mbot_navigation nav_cloister_demo.launch",
        ]
    ),
}
"""Each group's long-running commands run together (a launch and what the page starts beside
it in a second terminal), then its ``beside`` commands."""
WITHOUT_VIEWER = {
    "belvedere launch rbx1_bringup fake_turtlebot.launch",
    "belvedere launch rbx1_nav fake_move_base_blank_map.launch",
}
"""Launches without rviz: they say which graph they run on, and ``run rviz rviz`` shows them."""


def shown_after(command: str) -> list[str]:
    """The output the tutorial shows for ``command``: the plain block after the ``sh`` block
    that has it, each line as printed (a line the page wraps is joined again; ``…/`` stands
    for the directory before a path)."""
    text = TUTORIAL.read_text()
    blocks = list(re.finditer(r"```(\w*)\n(.*?)```", text, re.S))
    at = next(
        k for k, b in enumerate(blocks) if b.group(1) == "sh" and command in _commands(b.group(2))
    )
    shown = blocks[at + 1]
    assert shown.group(1) == "", f"no output shown after {command!r}"
    lines = shown.group(2).splitlines()
    if lines[0].startswith("…/"):  # one diagnostic, wrapped to the page's width
        return [" ".join(lines).removeprefix("…/")]
    return lines


FINITE: dict[str, list[str]] = {
    f"belvedere xacro {MBOT} -o mbot.urdf": [],
    "belvedere check mbot.urdf": shown_after("belvedere check mbot.urdf"),
    f"belvedere check {MBOT}": shown_after(f"belvedere check {MBOT}"),
    "belvedere map show examples/mbot_navigation/maps/cloister_gmapping.yaml "
    "-o docs/images/cloister_map.png": [],
}
"""Commands that end by themselves, with the lines the page shows of their output."""


def planned() -> set[str]:
    every = set(SETUP) | set(ELSEWHERE) | set(FINITE)
    for section in SECTIONS.values():
        every |= {*section.serve, *section.beside}
    return {_normal(c) for c in every}


def test_every_command_of_the_pages_is_run() -> None:
    missing = [
        c
        for page in (TUTORIAL, README)
        for c in page_commands(page)
        if c not in planned() and _normal(c) not in planned()
    ]
    assert not missing, f"commands of the pages no test runs: {missing}"


# --- running them ----------------------------------------------------------------------------
@pytest.fixture
def clone(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A user's directory as the pages assume: ``examples/`` (linked), ``docs/images/``, a
    ``my.world`` saved from the viewer (§7), and ROS_PACKAGE_PATH set."""
    (tmp_path / "examples").symlink_to(EXAMPLES)
    (tmp_path / "docs" / "images").mkdir(parents=True)
    shutil.copy(EXAMPLES / "mbot_gazebo/worlds/playground.world", tmp_path / "my.world")
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "examples"))
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(sys.path))
    return tmp_path


def _argv(command: str) -> list[str]:
    words = shlex.split(command, comments=True)
    assert words[0] == "belvedere"
    return [sys.executable, "-m", "belvedere", *words[1:]]


class Running:
    """A command started in ``cwd``, its stdout and stderr read as they come."""

    def __init__(self, command: str, cwd: Path) -> None:
        self.command = command
        self.proc = subprocess.Popen(
            _argv(command),
            cwd=cwd,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        self.lines: list[str] = []
        for stream in (self.proc.stdout, self.proc.stderr):
            threading.Thread(target=self._read, args=(stream,), daemon=True).start()

    def _read(self, stream: Iterator[str] | None) -> None:
        assert stream is not None
        for line in stream:
            self.lines.append(line.rstrip("\n"))

    def url(self) -> str | None:
        return next((m.group(0) for line in self.lines if (m := URL.search(line))), None)

    def serving(self) -> str:
        """Its viewer's address once the viewer's page answers."""

        def answered() -> str | None:
            assert self.proc.poll() is None, f"{self.command} ended: {self.lines}"
            url = self.url()
            if url is None:
                return None
            with urllib.request.urlopen(url, timeout=10) as page:  # loopback only
                return url if page.status == 200 else None

        found = wait_until(answered, what=f"{self.command}'s viewer", timeout=START_S)
        assert isinstance(found, str)
        return found

    def interrupt(self) -> None:
        """Ctrl-C, then its exit: cleanly, with no traceback."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
        try:
            self.proc.wait(timeout=60)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
            pytest.fail(f"{self.command} did not end on Ctrl-C: {self.lines[-20:]}")
        time.sleep(0.2)  # the readers' last lines
        assert not any("Traceback" in line for line in self.lines), self.lines


IN_A_TERMINAL = {"belvedere map show cloister.yaml"}
"""Commands whose output the page shows as typed in a terminal (``map show`` writes
``MAP.png`` there, and the picture itself to a pipe)."""


def _finish(command: str, cwd: Path, expect: list[str]) -> list[str]:
    terminal = os.openpty() if command in IN_A_TERMINAL else None
    done = subprocess.run(
        _argv(command),
        cwd=cwd,
        stdout=terminal[1] if terminal else subprocess.PIPE,
        stderr=subprocess.PIPE,
        timeout=START_S,
        check=False,
    )
    out = done.stdout or b""
    if terminal is not None:
        os.close(terminal[1])
        with os.fdopen(terminal[0], "rb") as shown:
            try:
                out = shown.read()
            except OSError:  # the terminal's end once it is read out
                out = b""
    lines = (out + done.stderr).decode(errors="replace").splitlines()
    assert done.returncode == 0, (command, lines)
    assert b"Traceback" not in done.stderr, (command, lines)
    for line in expect:
        assert any(line in seen for seen in lines), (command, line, lines)
    return lines


def test_the_finite_commands_print_what_the_pages_show(clone: Path) -> None:
    for command, expect in FINITE.items():
        _finish(command, clone, expect)
    assert (clone / "mbot.urdf").is_file()
    assert (clone / "docs/images/cloister_map.png").is_file()


@pytest.mark.parametrize("name", sorted(SECTIONS))
def test_a_section_runs_as_the_pages_say(name: str, clone: Path) -> None:
    section = SECTIONS[name]
    started: list[Running] = []
    try:
        for command in section.serve:
            if section.one_by_one:
                while started:
                    started.pop().interrupt()
            started.append(Running(command, clone))
            if command not in WITHOUT_VIEWER:
                started[-1].serving()
            else:
                wait_until(
                    lambda run=started[-1]: any("graph:" in line for line in run.lines),  # type: ignore[misc]
                    what=f"{command} on its graph",
                    timeout=START_S,
                )
        for command in section.beside:
            if command == "belvedere map show cloister.yaml":
                _finish(command, clone, [])
                assert (clone / "cloister.png").read_bytes().startswith(b"\x89PNG")
            elif command in section.running:
                beside = Running(command, clone)
                time.sleep(2.0)
                assert beside.proc.poll() is None, beside.lines
                beside.interrupt()
            else:
                _finish(command, clone, section.expect.get(command, []))
    finally:
        for run in reversed(started):
            run.interrupt()
