"""rqt_image_view's delivered frame rate in a real browser, against the camera's 30 Hz.

The course's camera robot (mbot_with_camera_gazebo.xacro, 1280 x 720 at 30 Hz) turns in place
in the playground world (MuJoCo, real time), so every frame differs, while Debian's Chromium,
headless, shows rqt_image_view's page on /camera/image_raw. Measured over a window of wall
time, after the first frame is shown:

1. frames the camera published, and the page subscribed to (queue size 1: newest only);
2. frames the page converted and handed to viser (JPEG-encoded);
3. frames delivered: the new pictures the browser's page displayed (each a new ``blob:``
   URL on the image, counted in the page).

    python benchmarks/rqt_image_view.py [--seconds 10]
"""

from __future__ import annotations

import argparse
import shutil
import socket
import sys
import time
from pathlib import Path

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph
from belvedere.packages import PackageIndex
from belvedere.sim.physics import PhysicsSimulation
from belvedere.viewer import ImagePage, ToolPage
from belvedere.viewer._chromium import launch_chromium
from belvedere.world import read_world

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
ROBOT = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_with_camera_gazebo.xacro"
WORLD = EXAMPLES / "mbot_gazebo/worlds/playground.world"
COUNT_FRAMES = """() => {
  window.__frames = 0;
  let last = null;
  const note = (img) => {
    if (img.src.startsWith('blob:') && img.src !== last) { last = img.src; window.__frames++; }
  };
  new MutationObserver((changes) => changes.forEach((c) => {
    if (c.target.tagName === 'IMG') note(c.target);
    c.addedNodes.forEach((n) => {
      if (n.querySelectorAll) n.querySelectorAll('img').forEach(note);
    });
  })).observe(document.body, {subtree: true, childList: true, attributes: true,
                              attributeFilter: ['src']});
}"""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
        return port


def measure(seconds: float) -> None:
    from playwright.sync_api import sync_playwright

    chromium = shutil.which("chromium")
    if chromium is None:
        sys.exit("Debian's chromium is not installed (apt-get install chromium)")
    packages = PackageIndex([EXAMPLES])
    graph = Graph()
    sim = PhysicsSimulation(graph, read_world(WORLD, packages=packages))
    sim.spawn(RobotModel.from_path(ROBOT), name="mbot", packages=packages)
    turn = graph.create_node("driver").publisher("/cmd_vel", "geometry_msgs/Twist")
    page_server = ToolPage("rqt_image_view", port=free_port())
    view = ImagePage(graph.create_node("rqt_image_view"), page_server)
    graph.start(rtf=1.0)
    try:
        with sync_playwright() as p:
            browser = launch_chromium(p, chromium)
            page = browser.new_page(viewport={"width": 1100, "height": 760})
            page.goto(view.page.url)
            page.evaluate(COUNT_FRAMES)
            turn.publish_data({"angular": {"z": 0.6}})
            deadline = time.monotonic() + 120
            while page.evaluate("window.__frames") < 2 and time.monotonic() < deadline:
                time.sleep(0.05)
            received, sent = view.received, view.sent
            shown = page.evaluate("window.__frames")
            start = time.monotonic()
            time.sleep(seconds)
            wall = time.monotonic() - start
            shown = page.evaluate("window.__frames") - shown
            received, sent = view.received - received, view.sent - sent
            browser.close()
    finally:
        view.close()
        graph.shutdown()
    print(f"rqt_image_view, camera 1280x720 at 30 Hz, {wall:.1f} s of wall time")
    print(f"  frames received (queue 1)   {received / wall:6.1f} /s")
    print(f"  frames sent to the page     {sent / wall:6.1f} /s")
    print(f"  frames shown in the browser {shown / wall:6.1f} /s   (goal >= 25)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--seconds", type=float, default=10.0)
    measure(parser.parse_args().seconds)


if __name__ == "__main__":
    main()
