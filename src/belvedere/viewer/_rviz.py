"""Reading an rviz ``.rviz`` config: the fixed frame and the enabled displays with topics."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from belvedere.errors import BelvedereError

__all__ = ["RvizConfig", "RvizDisplay", "read_rviz"]

KNOWN = {
    "rviz/Grid": "Grid",
    "rviz/RobotModel": "RobotModel",
    "rviz/TF": "TF",
    "rviz/LaserScan": "LaserScan",
    "rviz/PointCloud2": "PointCloud2",
    "rviz/Map": "OccupancyGrid",
    "rviz/Odometry": "Odometry",
    "rviz/Path": "Path",
    "rviz/Pose": "PoseStamped",
    "rviz/PoseArray": "PoseArray",
    "rviz/Marker": "Marker",
    "rviz/MarkerArray": "MarkerArray",
    "rviz/Image": "Image",
    "rviz/Camera": "Camera",
}


@dataclass
class RvizDisplay:
    kind: str
    """Our display kind (``LaserScan``, ``OccupancyGrid``…)."""
    name: str
    topic: str | None
    options: dict[str, Any] = field(default_factory=dict)
    cls: str = ""
    enabled: bool = True
    properties: dict[str, Any] = field(default_factory=dict)


@dataclass
class RvizView:
    cls: str = "rviz/Orbit"
    name: str = "Current View"
    properties: dict[str, Any] = field(default_factory=dict)


@dataclass
class RvizConfig:
    fixed_frame: str = "map"
    displays: list[RvizDisplay] = field(default_factory=list)
    unknown: list[str] = field(default_factory=list)
    """Display classes we do not draw (listed once, not fatal)."""
    background: tuple[int, int, int] | None = None
    frame_rate: int = 30
    view: RvizView | None = None


def read_rviz(path: str | Path) -> RvizConfig:
    file = Path(path)
    try:
        data = yaml.safe_load(file.read_text(encoding="utf-8"))
    except OSError as err:
        msg = f"cannot read rviz config {file}: {err.strerror}"
        raise BelvedereError(msg) from None
    except yaml.YAMLError as err:
        msg = f"{file}: not a valid rviz config (YAML): {err}"
        raise BelvedereError(msg) from None
    manager = (data or {}).get("Visualization Manager", {}) if isinstance(data, dict) else {}
    config = RvizConfig()
    current = ((manager.get("Views") or {}).get("Current")) or {}
    if isinstance(current, dict) and current.get("Class"):
        props = {k: v for k, v in current.items() if k not in ("Class", "Name")}
        config.view = RvizView(str(current["Class"]), str(current.get("Name", "")), props)
    frame = (manager.get("Global Options") or {}).get("Fixed Frame")
    if frame:
        config.fixed_frame = str(frame)
    for item in manager.get("Displays") or []:
        if not isinstance(item, dict) or not item.get("Enabled", True):
            continue
        cls = str(item.get("Class", ""))
        kind = KNOWN.get(cls) or KNOWN.get(cls.replace("rviz_default_plugins/", "rviz/"))
        if kind is None:
            if cls not in config.unknown:
                config.unknown.append(cls)
            continue
        topic = item.get("Topic")
        if isinstance(topic, dict):  # ROS 2 rviz: {Value: /scan, …}
            topic = topic.get("Value")
        props = {k: v for k, v in item.items() if k not in ("Class", "Name", "Enabled")}
        config.displays.append(
            RvizDisplay(kind, str(item.get("Name", kind)), topic, item, cls, True, props)
        )
    return config
