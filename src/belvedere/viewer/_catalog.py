"""The display types the viewer offers, by rviz's names (and the older names belvedere used)."""

from __future__ import annotations

from typing import Any

from belvedere.viewer._display import Display
from belvedere.viewer._displays import (
    CameraDisplay,
    ImageDisplay,
    LaserScanDisplay,
    MapDisplay,
    PointCloud2Display,
)
from belvedere.viewer._frame_displays import AxesDisplay, GridDisplay, RobotModelDisplay, TFDisplay
from belvedere.viewer._shapes import (
    MarkerArrayDisplay,
    MarkerDisplay,
    OdometryDisplay,
    PathDisplay,
    PointStampedDisplay,
    PolygonDisplay,
    PoseArrayDisplay,
    PoseDisplay,
)
from belvedere.viewer._status import Level

__all__ = ["DISPLAYS", "UnsupportedDisplay", "display_type"]

DISPLAYS: dict[str, type[Display]] = {
    d.type_name: d
    for d in (
        AxesDisplay,
        CameraDisplay,
        GridDisplay,
        ImageDisplay,
        LaserScanDisplay,
        MapDisplay,
        MarkerArrayDisplay,
        MarkerDisplay,
        OdometryDisplay,
        PathDisplay,
        PointCloud2Display,
        PointStampedDisplay,
        PolygonDisplay,
        PoseArrayDisplay,
        PoseDisplay,
        RobotModelDisplay,
        TFDisplay,
    )
}
"""Display types by the name rviz's Add dialog shows."""

_ALIASES: dict[str, tuple[str, dict[str, Any]]] = {
    "OccupancyGrid": ("Map", {}),
    "Costmap": ("Map", {"Color Scheme": "costmap"}),
    "PoseStamped": ("Pose", {}),
    "ParticleCloud": ("PoseArray", {}),
}
_BY_CLASS = {d.cls: d for d in DISPLAYS.values()}


def display_type(name: str) -> tuple[type[Display], dict[str, Any]] | None:
    """The display type for a name (``LaserScan``), an rviz class (``rviz/LaserScan``,
    ``rviz_default_plugins/LaserScan``) or an older alias, with the values the alias implies."""
    if name in DISPLAYS:
        return DISPLAYS[name], {}
    if name in _ALIASES:
        target, values = _ALIASES[name]
        return DISPLAYS[target], dict(values)
    cls = name.replace("rviz_default_plugins/", "rviz/")
    if cls in _BY_CLASS:
        return _BY_CLASS[cls], {}
    return None


class UnsupportedDisplay(Display):
    """A display class of a config that belvedere does not draw: listed, in Error, and kept
    (with its values) when the config is saved again."""

    type_name = "Unsupported"
    stamped = False

    def __init__(self, *args: Any, rviz_class: str, **kwargs: Any) -> None:
        self.rviz_class_name = rviz_class
        super().__init__(*args, **kwargs)
        self.status.set(
            "Plugin",
            Level.ERROR,
            f"The class required for this display, '{rviz_class}', could not be loaded.",
        )

    @property
    def rviz_class(self) -> str:
        return self.rviz_class_name
