"""The viewer's frame rate in a real browser, against its 30 Hz target (rviz's default).

The course's mbot drives in a circle (kinematic engine, real time) while Debian's Chromium,
headless with software WebGL, shows the viewer with a 360-beam LaserScan at 10 Hz (in the
laser's frame, drawn with the transform at its stamp), a 400 x 400 Map and a 200-pose Path.
After the robot is first drawn and viser's adaptive resolution has settled (``--settle``
seconds: it lowers the pixel ratio a step per 2.5 s of slow frames), measured over a window of
wall time:

1. how long the browser takes to draw the robot first (shaders compiled on the CPU), seen in
   a screenshot: the camera looks at the robot, so the view's centre turns the base's yellow;
2. viewer updates per second: scene updates the viewer sends (its render loop, target 30 Hz);
3. browser frames per second: the renders three.js made in the page (and, beside them, the
   page's ``requestAnimationFrame`` callbacks);
4. the viewer's render thread's share of one core (CPU time over wall time; goal <= 10 %).

Software WebGL is fill-bound: a surface covering the view (the map, seen from near the robot)
costs most of a frame, so the rate depends on the view's size: the page's (``--viewport``)
less the panel docked beside it. The machine's other load moves the rate by several frames a
second from one moment to the next, so the window is cut into ``--windows`` parts and the
median is reported beside the range.

``--breakdown`` then says what each kind of thing drawn costs a frame: it hides one kind in
the page (viser's full-view background pass, the map, the lines, the robot, the scan) and
measures again, each interleaved with the whole scene so both see the same load.
``--antialias both`` draws the scene twice in the same run, with WebGL's 4x multisampling
(a browser's default, and the tests') and without it (the default here: what software
rendering should use, :mod:`belvedere.viewer._chromium`), and prints their ratio.
``--pixel-ratio R`` fixes the pixel ratio (viser's ``fixedDpr``: no adaptive resolution), so
two runs draw the same pixels. ``--still``: the robot stands and no scan comes, so nothing
changes and the page should draw only viser's one frame a second.

    python benchmarks/viewer.py [--seconds 10] [--viewport 1000x700] [--breakdown]
        [--antialias off|on|both] [--pixel-ratio R] [--still]
"""

from __future__ import annotations

import argparse
import math
import shutil
import socket
import statistics
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph
from belvedere.sim.kinematic import KinematicSimulation
from belvedere.viewer import Viewer
from belvedere.viewer._chromium import launch_chromium

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
MBOT = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_gazebo.xacro"
TARGET_HZ = 30.0
RENDERS = "() => window.__viserTestpoints.rendererInfo.render.frame"
"""The scene renders three.js has made (viser exposes its renderer's counters)."""
VIEW = """() => {
    const c = window.__viserMutable.canvas, box = c.getBoundingClientRect();
    return [box.width, box.height, c.width, c.height];
}"""
LAYERS = {
    "background pass": "o.material && o.material.uniforms && o.material.uniforms.depthMap",
    "map": "o.isMesh && o.material && o.material.map && o.material.type === 'MeshBasicMaterial'",
    "lines (grid, path, TF)": "o.type === 'LineSegments2' || o.type === 'LineSegments'",
    "robot": "o.isMesh && o.material && o.material.type === 'MeshStandardMaterial'",
    "scan": "o.isPoints",
}
"""Kinds of things drawn, as three.js objects in viser's scene: ``o`` is one."""
HIDE = """(test) => {
    const hidden = [];
    window.__viserMutable.scene.traverse((o) => {
        if (o.visible && new Function("o", "return " + test)(o)) {
            o.visible = false;
            hidden.push(o);
        }
    });
    window.__hidden = hidden;
    return hidden.length;
}"""
SHOW = (
    "() => { (window.__hidden || []).forEach((o) => { o.visible = true; }); window.__hidden = []; }"
)
COUNT_FRAMES = """() => {
    window.__frames = 0;
    const tick = () => { window.__frames += 1; requestAnimationFrame(tick); };
    requestAnimationFrame(tick);
}"""


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


def _robot_drawn(page: Any) -> bool:
    from io import BytesIO

    from PIL import Image

    box = page.locator("canvas").first.bounding_box()
    if box is None or box["x"] == 0:
        return False  # the panel is not docked beside the view yet
    x, y = round(box["x"] + box["width"] / 2), round(box["y"] + box["height"] / 2)
    shot = page.screenshot(clip={"x": x, "y": y, "width": 1, "height": 1})
    r, _, b = Image.open(BytesIO(shot)).convert("RGB").getpixel((0, 0))  # type: ignore[misc]
    return bool(r > 200 and r - b > 100)  # URDF "yellow" (rgba 1 0.4 0), lit


def _rate(page: Any, seconds: float) -> float:
    """Renders a second in the page over ``seconds`` of wall time."""
    drawn0, t0 = page.evaluate(RENDERS), time.perf_counter()
    time.sleep(seconds)
    return float(page.evaluate(RENDERS) - drawn0) / (time.perf_counter() - t0)


def _summary(rates: list[float]) -> str:
    median = statistics.median(rates)
    return (
        f"{median:5.1f} fps (target {TARGET_HZ:g}; {median / TARGET_HZ:.0%}; "
        f"{min(rates):.1f}-{max(rates):.1f} over {len(rates)} windows)"
    )


def _browse(
    p: Any, viewer: Viewer, args: argparse.Namespace, antialias: bool
) -> tuple[float, list[float]]:
    """Open the viewer in a new Chromium; print its rates; the median and the windows'."""
    chromium = shutil.which("chromium")
    if chromium is None:
        sys.exit("Debian's chromium is not installed (apt-get install chromium)")
    browser = launch_chromium(p, chromium, antialias=antialias)
    try:
        page = browser.new_page(viewport={"width": args.viewport[0], "height": args.viewport[1]})
        page.set_default_timeout(300_000)
        started = time.perf_counter()
        url = viewer.url
        if args.pixel_ratio:
            url += ("&" if "?" in url else "?") + f"fixedDpr={args.pixel_ratio:g}"
        page.goto(url)
        page.wait_for_selector("canvas")
        while not _robot_drawn(page):
            time.sleep(0.1)
        first = time.perf_counter() - started
        time.sleep(args.settle)  # viser's adaptive resolution steps every 2.5 s of slow frames
        page.evaluate(COUNT_FRAMES)
        sent0, t0, cpu0 = viewer.frames_rendered, time.perf_counter(), viewer.render_cpu_s
        rates = [_rate(page, args.seconds / args.windows) for _ in range(args.windows)]
        sent1, raf = viewer.frames_rendered, page.evaluate("() => window.__frames")
        wall = time.perf_counter() - t0
        cpu = (viewer.render_cpu_s - cpu0) / wall
        width, height, pixels_w, pixels_h = page.evaluate(VIEW)
        sent = (sent1 - sent0) / wall
        samples = page.evaluate(
            "() => window.__viserMutable.canvas.getContext('webgl2').getParameter(0x80A9)"
        )  # SAMPLES: 4 with the browser's antialiasing, 0 without
        print(f"-- WebGL antialiasing {'on' if antialias else 'off'} ({samples} samples a pixel)")
        print(f"page {args.viewport[0]} x {args.viewport[1]}; its 3D view {width:g} x {height:g}")
        print(
            f"  CSS pixels, drawn at {pixels_w} x {pixels_h} (pixel ratio {pixels_w / width:.3g})"
        )
        print(f"robot first drawn in the browser: {first:.1f} s after loading the page")
        print(f"viewer updates:  {sent:5.1f} Hz (target {TARGET_HZ:g} Hz; {sent / TARGET_HZ:.0%})")
        print(f"browser frames:  {_summary(rates)}")
        print(f"  (page frames:  {raf / wall:5.1f} per second, requestAnimationFrame)")
        print(f"render thread:   {cpu:5.1%} of one core (goal <= 10 %; {cpu / 0.10:.2f} of it)")
        if args.breakdown:
            _breakdown(page, args)
        return statistics.median(rates), rates
    finally:
        browser.close()


def _breakdown(page: Any, args: argparse.Namespace) -> None:
    """Each kind of thing drawn hidden in turn, interleaved with the whole scene."""
    window = args.seconds / args.windows
    whole: list[float] = []
    without: dict[str, list[float]] = {name: [] for name in LAYERS}
    for _ in range(args.windows):
        for name, test in LAYERS.items():
            whole.append(_rate(page, window))
            page.evaluate(HIDE, test)
            time.sleep(0.3)  # the frame in flight still has it
            without[name].append(_rate(page, window))
            page.evaluate(SHOW)
            time.sleep(0.3)
    full = statistics.median(whole)
    print(f"what a frame costs: the whole scene {full:.1f} fps ({1000 / full:.0f} ms a frame);")
    for name, rates in without.items():
        rate = statistics.median(rates)
        saved = 1000 / full - 1000 / rate
        print(f"  without the {name:24s} {rate:5.1f} fps: it costs {saved:4.0f} ms a frame")


def measure(args: argparse.Namespace) -> None:
    from playwright.sync_api import sync_playwright

    model = RobotModel.from_path(MBOT)
    graph = Graph()
    sim = KinematicSimulation(graph, model)
    viewer = Viewer(graph, model=model, port=_free_port(), fixed_frame=sim.odom_frame, sim=sim)
    viewer.add_display("LaserScan", "/scan", values={"Size (m)": 0.03})
    viewer.add_display("Map", "/map")
    viewer.add_display("Path", "/plan")
    node = graph.create_node("driver")
    cmd = node.publisher("/cmd_vel", "geometry_msgs/Twist", latch=True)
    if not args.still:
        cmd.publish_data({"linear": {"x": 0.2}, "angular": {"z": 0.5}})
    _publish_world(node, sim.odom_frame or "odom", scan=not args.still)
    graph.start(rtf=1.0)
    modes = {"off": [False], "on": [True], "both": [True, False]}[args.antialias]
    try:
        with sync_playwright() as p:
            medians = [_browse(p, viewer, args, antialias)[0] for antialias in modes]
    finally:
        viewer.close()
        graph.shutdown()
    if len(medians) == 2:
        print(f"frames without antialiasing / with it: {medians[1] / medians[0]:.2f}")


def _publish_world(node: Any, odom: str, *, scan: bool = True) -> None:
    """A 360-beam scan at 10 Hz (stamped now, in the laser's frame; unless not ``scan``), a
    400 x 400 map and a path, all in the odometry frame the robot drives in."""
    size = 400
    yy, xx = np.mgrid[0:size, 0:size]
    cells = np.where((xx % 40 < 2) | (yy % 40 < 2), 100, 0).astype(np.int8)
    cells[:50, :50] = -1
    node.publisher("/map", "nav_msgs/OccupancyGrid", latch=True).publish_data(
        {
            "header": {"frame_id": odom},
            "info": {
                "resolution": 0.05,
                "width": size,
                "height": size,
                "origin": {"position": {"x": -10.0, "y": -10.0}},
            },
            "data": cells.ravel().tolist(),
        }
    )
    angles = np.linspace(0, 2 * np.pi, 200)
    node.publisher("/plan", "nav_msgs/Path", latch=True).publish_data(
        {
            "header": {"frame_id": odom},
            "poses": [
                {"pose": {"position": {"x": 2 * math.cos(a), "y": 2 * math.sin(a)}}}
                for a in angles.tolist()
            ],
        }
    )
    if not scan:
        return
    scans = node.publisher("/scan", "sensor_msgs/LaserScan")
    ranges = (3.0 + 0.5 * np.sin(np.arange(360) / 10)).tolist()

    def tick() -> None:
        now = node.now_ns()
        scans.publish_data(
            {
                "header": {"frame_id": "base_link", "stamp": [now // 10**9, now % 10**9]},
                "angle_min": -math.pi,
                "angle_max": math.pi,
                "angle_increment": 2 * math.pi / 360,
                "range_min": 0.1,
                "range_max": 10.0,
                "ranges": ranges,
            }
        )

    node.timer(0.1, tick)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--seconds", type=float, default=10.0, help="measuring window")
    parser.add_argument("--settle", type=float, default=6.0, help="seconds drawn before measuring")
    parser.add_argument("--viewport", default="1000x700", help="the page's size, WxH pixels")
    parser.add_argument("--windows", type=int, default=4, help="parts of the window (a median)")
    parser.add_argument("--breakdown", action="store_true", help="what each kind drawn costs")
    parser.add_argument("--pixel-ratio", type=float, default=0.0, help="fixed (0: viser's own)")
    parser.add_argument("--still", action="store_true", help="nothing moves: frames not drawn")
    parser.add_argument(
        "--antialias", choices=("off", "on", "both"), default="off", help="WebGL multisampling"
    )
    args = parser.parse_args()
    w, _, h = args.viewport.partition("x")
    args.viewport = (int(w), int(h))
    measure(args)


if __name__ == "__main__":
    main()
