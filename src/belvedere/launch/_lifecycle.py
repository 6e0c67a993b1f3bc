"""Nodes live and die as roslaunch's process monitor has them (ros_comm's ``pmon.py``).

Every node a launch starts is a process: a script is one, and so is a node belvedere runs in
its own process (its start or its run raising is that process dying with exit code 1; a node
that ends by itself, as map_saver does, exits with its status). When one ends:

=========================  ===============================================  =========  ======
node                       roslaunch prints                                 restarts   ends
=========================  ===============================================  =========  ======
ordinary, exit 0           ``[name-N] process has finished cleanly``        no         no
ordinary, exit ≠ 0         ``[name-N] process has died [pid …, exit code    no         no
                           C, cmd …].``
``respawn="true"``         the same line, then ``respawn_delay`` seconds    yes        no
                           of wall time later ``[name-N] restarting
                           process``
``required="true"``        ``REQUIRED process [name-N] has died!`` between  no         yes
                           two rules of ``=``, with the line above and
                           ``Initiating shutdown!``
=========================  ===============================================  =========  ======

Each description ends with ``log file: DIR/name-N*.log``. The launch's exit status is 0
whichever way it ends, as roslaunch's is. A launch that joined a running graph (roslaunch
beside a running master) ends, as roslaunch does, once all its processes have died and none
will respawn; one that made the graph keeps it (and its master, as roslaunch keeps the
roscore it started) until Ctrl-C. Processes are numbered as roslaunch numbers them: from 2 on
a graph the launch made (process 1 is the rosout of roslaunch's own roscore), from 1 beside a
running one.

The log directory is ROS's (``ROS_LOG_DIR``, else ``ROS_HOME/log``, else ``~/.ros/log``) and
the launch's run id below it, made only when something is written there: what a script of
``output="log"`` prints on stdout (``name-N-stdout.log``), and why a node of this process
died (``name-N.log``).
"""

from __future__ import annotations

import logging
import os
import subprocess
import time
import traceback
import uuid
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO

from belvedere.errors import BelvedereError
from belvedere.graph import Node
from belvedere.launch._model import LaunchNode

__all__ = ["LaunchProcess", "ProcessMonitor", "ros_log_dir"]

logger = logging.getLogger("belvedere.launch")

RULE = "=" * 80
"""roslaunch's banner around a required process's death."""
VERBATIM = {"verbatim": True}
"""A record printed as written (no ``error:`` before roslaunch's own lines)."""


def ros_log_dir(environ: Mapping[str, str] | None = None) -> Path:
    """Where ROS keeps its logs (rospkg's ``get_log_dir``): ``ROS_LOG_DIR``, else
    ``ROS_HOME/log``, else ``~/.ros/log``."""
    env = os.environ if environ is None else environ
    if env.get("ROS_LOG_DIR"):
        return Path(env["ROS_LOG_DIR"])
    if env.get("ROS_HOME"):
        return Path(env["ROS_HOME"]) / "log"
    return Path(os.path.expanduser("~")) / ".ros" / "log"


@dataclass(eq=False)
class LaunchProcess:
    """One node the launch started, by roslaunch's name for it (``ns/name-N``)."""

    spec: LaunchNode
    name: str
    cmd: list[str]
    """roslaunch's ``cmd`` of it: the executable (``PKG/TYPE`` for a node of this process)
    and its arguments."""
    pid: int
    popen: subprocess.Popen[bytes] | None = None
    """A script's process; None for a node of this process."""
    node: Node | None = None
    exit_code: int | None = None
    """Set when it ends (a script's as ``Popen`` reports it: ``-N`` for signal N)."""
    died_at: float | None = None
    """``time.monotonic()`` when it was seen to end (roslaunch's respawn delay counts from
    then, in wall time)."""
    finished: Callable[[], int | None] = field(default=lambda: None)
    """A node of this process: its exit status once it has ended by itself, else None."""
    start: Callable[[], None] = field(default=lambda: None)
    """Start it again (respawn): gives it its new ``popen`` or ``node`` and ``pid``."""

    def alive(self) -> bool:
        if self.exit_code is None:
            if self.popen is not None:
                self.exit_code = self.popen.poll()
            elif self.node is not None and self.node.closed:
                self.exit_code = self.finished() or 0
        if self.exit_code is None:
            return True
        if self.died_at is None:
            self.died_at = time.monotonic()
        return False


class ProcessMonitor:
    """The launch's processes, polled as roslaunch's monitor polls them."""

    def __init__(self, *, joined: bool, environ: Mapping[str, str] | None = None) -> None:
        self.joined = joined
        self.log_dir = ros_log_dir(environ) / str(uuid.uuid1())
        self.procs: list[LaunchProcess] = []
        self.respawning: list[LaunchProcess] = []
        self.ended: LaunchProcess | None = None

    def log_file(self, process_name: str, suffix: str = "") -> Path:
        return self.log_dir / f"{process_name.replace('/', '-')}{suffix}.log"

    def add(self, process: LaunchProcess) -> None:
        self.procs.append(process)

    def stdout_for(self, process_name: str, *, append: bool) -> IO[bytes] | None:
        """The file a script of ``output="log"`` prints to (roslaunch appends for a node that
        respawns); None, with a warning, if it cannot be made."""
        path = self.log_file(process_name, "-stdout")
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            return open(path, "ab" if append else "wb")
        except OSError as err:
            logger.warning("cannot write %s: %s; its output is discarded", path, err.strerror)
            return None

    def failed(self, process: LaunchProcess, err: BaseException) -> None:
        """A node of this process raised while starting or running: what it says is its
        output, kept in its log file too, and it exits with status 1."""
        if isinstance(err, BelvedereError):
            text = err.describe()
        else:
            text = "".join(traceback.format_exception(err)).rstrip("\n")
        logger.error("%s", text, extra=VERBATIM)
        path = self.log_file(process.name)
        try:  # appended, as roslaunch appends to the logs of a node that respawns
            path.parent.mkdir(parents=True, exist_ok=True)
            with open(path, "a", encoding="utf-8") as log:
                log.write(text + "\n")
        except OSError as problem:
            logger.debug("cannot write %s: %s", path, problem.strerror)
        if process.node is not None and not process.node.closed:
            process.node.shutdown()
        process.exit_code = 1

    def describe(self, process: LaunchProcess) -> str:
        """roslaunch's description of how a process ended, with its log files."""
        code = process.exit_code
        if code:
            text = (
                f"process has died [pid {process.pid}, exit code {code}, "
                f"cmd {' '.join(process.cmd)}]."
            )
        else:
            text = "process has finished cleanly"
        return f"{text}\nlog file: {self.log_dir / process.name.replace('/', '-')}*.log"

    def poll(self) -> LaunchProcess | None:
        """Look at every process once, as one turn of roslaunch's monitor: report those
        that ended, restart those due to respawn. Returns the process whose end ends the
        launch (a required one, or the last of a joined launch's), if one did."""
        if self.ended is not None:
            return self.ended
        dead: list[LaunchProcess] = []
        for process in list(self.procs):
            if process.alive():
                continue
            described = self.describe(process)
            if process.spec.required:
                logger.error(
                    "%sREQUIRED process [%s] has died!\n%s\nInitiating shutdown!\n%s",
                    RULE,
                    process.name,
                    described,
                    RULE,
                    extra=VERBATIM,
                )
                self.ended = process
                return process
            if process not in self.respawning:
                level = logging.ERROR if process.exit_code else logging.INFO
                logger.log(level, "[%s] %s", process.name, described, extra=VERBATIM)
                dead.append(process)
        for process in dead:
            if process.spec.respawn:
                self.respawning.append(process)
            else:
                self.procs.remove(process)
        if self.joined and dead and not self.procs and not self.respawning:
            logger.info("all processes on machine have died, roslaunch will exit")
            self.ended = dead[-1]
            return self.ended
        now = time.monotonic()
        for process in list(self.respawning):
            assert process.died_at is not None
            if now - process.died_at >= process.spec.respawn_delay:
                self.respawning.remove(process)
                logger.info("[%s] restarting process", process.name)
                process.exit_code = process.died_at = None
                process.start()
        return None

    def stopping(self) -> None:
        """roslaunch's lines as it stops the processes: each still registered, last first."""
        for process in reversed(self.procs):
            logger.info("[%s] killing on exit", process.name)
        logger.info("shutting down processing monitor...")

    @staticmethod
    def stopped() -> None:
        logger.info("... shutting down processing monitor complete")
        logger.info("done")
