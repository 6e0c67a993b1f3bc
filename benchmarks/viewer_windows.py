"""A script's cv2 window in the viewer: the frames a 640 x 480 window shown at 30 Hz reaches
the browser with, and what showing it costs the viewer.

A script run as belvedere runs scripts (``belvedere run``, a process of its own) shows a
moving 640 x 480 picture with ``cv2.imshow`` at 30 Hz (``rospy.Rate``); the viewer, in this
process on the same graph, shows the window in its panel while Debian's Chromium, headless,
has the viewer's page open. Measured over a window of wall time, after the first frame is
shown, each as a ratio against the reference measured in the same run — the frames the
script published (it prints its count):

1. frames the viewer received (queue size 1: newest only) and the page displayed (each a new
   ``blob:`` URL on the picture), per frame published;
2. the viewer's render thread's CPU time per published frame (all its work: the window's
   picture converted and JPEG-encoded, and the rest of the page's frame) against the frame
   budget of one core at 30 Hz (1/30 s): below 1 keeps up on one core.

    python benchmarks/viewer_windows.py [--seconds 10]
"""

from __future__ import annotations

import argparse
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from belvedere.graph import Graph, ZenohTransport
from belvedere.viewer import Viewer
from belvedere.viewer._chromium import launch_chromium
from rqt_image_view import COUNT_FRAMES, free_port

RATE = 30.0
SCRIPT = """\
import sys
import numpy as np
import cv2
import rospy

rospy.init_node("window_bench")
base = np.zeros((480, 640, 3), np.uint8)
base[..., 0] = np.arange(640, dtype=np.uint8)[None, :]
base[..., 1] = np.arange(480, dtype=np.uint8)[:, None] // 2
rate = rospy.Rate(30)
shown = 0
while not rospy.is_shutdown():
    cv2.imshow("bench", np.roll(base, 7 * shown, axis=1))  # every frame differs
    cv2.waitKey(1)
    shown += 1
    if shown % 30 == 0:
        print(shown, flush=True)
    try:
        rate.sleep()
    except rospy.ROSInterruptException:
        break
"""


class Published:
    """The script's count of frames shown (the last line it printed)."""

    def __init__(self, proc: subprocess.Popen[str]) -> None:
        self.proc = proc
        self.count = 0
        import threading

        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            if line.strip().isdigit():
                self.count = int(line)


def received(viewer: Viewer) -> int:
    windows: Any = viewer.windows.windows
    return sum(int(w.received) for w in windows.values())


def measure(seconds: float) -> None:
    from playwright.sync_api import sync_playwright

    chromium = shutil.which("chromium")
    if chromium is None:
        sys.exit("Debian's chromium is not installed (apt-get install chromium)")
    # a graph of the benchmark's own: never a user's
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    env = {**os.environ, "BELVEDERE_ENDPOINT": endpoint, "BELVEDERE_DOMAIN": "230"}
    os.environ.update(env)
    graph = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint, serve_params=False))
    viewer = Viewer(graph, port=free_port())
    graph.start(rtf=None)
    with tempfile.TemporaryDirectory() as tmp:
        script = Path(tmp) / "window_bench.py"
        script.write_text(SCRIPT)
        proc = subprocess.Popen(
            [sys.executable, "-m", "belvedere", "run", str(script)],
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            text=True,
            env=env,
        )
        published = Published(proc)
        try:
            with sync_playwright() as p:
                browser = launch_chromium(p, chromium)
                page = browser.new_page(viewport={"width": 1400, "height": 800})
                page.goto(viewer.url)
                page.evaluate(COUNT_FRAMES)
                deadline = time.monotonic() + 120
                while page.evaluate("window.__frames") < 2 and time.monotonic() < deadline:
                    time.sleep(0.05)
                shown, got = page.evaluate("window.__frames"), received(viewer)
                cpu, sent = viewer.render_cpu_s, published.count
                start = time.monotonic()
                time.sleep(seconds)
                wall = time.monotonic() - start
                shown = page.evaluate("window.__frames") - shown
                got = received(viewer) - got
                cpu = viewer.render_cpu_s - cpu
                sent = published.count - sent
                browser.close()
        finally:
            proc.send_signal(signal.SIGINT)
            proc.wait(timeout=60)
            viewer.close()
            graph.shutdown()
    budget = 1.0 / RATE
    per_frame = cpu / max(1, sent)
    print(f"cv2 window 640x480 at {RATE:g} Hz in the viewer, {wall:.1f} s of wall time")
    print(f"  frames published by the script {sent / wall:6.1f} /s   (reference)")
    for label, count in (("received by the viewer ", got), ("shown in the browser   ", shown)):
        print(f"  frames {label} {count / wall:6.1f} /s   ratio {count / max(1, sent):.2f}")
    print(
        f"  viewer render CPU per frame    {per_frame * 1000:6.2f} ms   "
        f"ratio {per_frame / budget:.2f} of the 30 Hz budget (1/30 s, one core)"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=10.0)
    measure(parser.parse_args().seconds)


if __name__ == "__main__":
    main()
