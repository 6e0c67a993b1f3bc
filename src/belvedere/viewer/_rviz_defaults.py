"""What rviz 1.14 gives each display and view property it is not told: the facts behind
:mod:`belvedere.viewer._rviz`.

Every value is what rviz 1.14 itself writes (through its ``save_config`` service) for a display
or view it created with nothing set; ``tests/viewer/test_rviz.py`` checks the table against
Debian's rviz. A ``/`` joins a property to its sub-property (``Line Style/Line Width``).
"""

from __future__ import annotations

from typing import Any, Final

__all__ = ["DEFAULTS", "GLOBAL_DEFAULTS", "GROUP", "TOPIC_KEYS", "VIEW_DEFAULTS"]

GROUP: Final = "rviz/Group"

TOPIC_KEYS: Final = {
    "rviz/Image": "Image Topic",
    "rviz/Camera": "Image Topic",
    "rviz/Marker": "Marker Topic",
    "rviz/MarkerArray": "Marker Topic",
    "rviz/InteractiveMarkers": "Update Topic",
}
"""Where a display keeps its topic when it is not ``Topic``."""

_SUBSCRIBER: Final[dict[str, Any]] = {"Topic": "", "Queue Size": 10, "Unreliable": False}
_CLOUD: Final[dict[str, Any]] = {
    **_SUBSCRIBER,
    "Selectable": True,
    "Style": "Flat Squares",
    "Size (m)": 0.01,
    "Size (Pixels)": 3.0,
    "Alpha": 1.0,
    "Decay Time": 0.0,
    "Position Transformer": "",
    "Color Transformer": "",
    "Color": "255; 255; 255",
    "Channel Name": "intensity",
    "Axis": "Z",
    "Use rainbow": True,
    "Invert Rainbow": False,
    "Min Color": "0; 0; 0",
    "Max Color": "255; 255; 255",
    "Autocompute Intensity Bounds": True,
    "Autocompute Value Bounds": True,
    "Autocompute Value Bounds/Min Value": -10.0,
    "Autocompute Value Bounds/Max Value": 10.0,
    "Use Fixed Frame": True,
}
_ARROW: Final[dict[str, Any]] = {
    "Shape": "Arrow",
    "Color": "255; 25; 0",
    "Alpha": 1.0,
    "Shaft Length": 1.0,
    "Shaft Radius": 0.05,
    "Head Length": 0.3,
    "Head Radius": 0.1,
    "Axes Length": 1.0,
    "Axes Radius": 0.1,
}
_COVARIANCE: Final[dict[str, Any]] = {
    "Covariance": True,
    "Covariance/Position": True,
    "Covariance/Position/Color": "204; 51; 204",
    "Covariance/Position/Alpha": 0.3,
    "Covariance/Position/Scale": 1.0,
    "Covariance/Orientation": True,
    "Covariance/Orientation/Color": "255; 255; 127",
    "Covariance/Orientation/Alpha": 0.5,
    "Covariance/Orientation/Scale": 1.0,
    "Covariance/Orientation/Offset": 1.0,
    "Covariance/Orientation/Frame": "Local",
    "Covariance/Orientation/Color Style": "Unique",
}
_OFFSET: Final[dict[str, Any]] = {"Offset/X": 0.0, "Offset/Y": 0.0, "Offset/Z": 0.0}

DEFAULTS: dict[str, dict[str, Any]] = {
    "rviz/Grid": {
        "Reference Frame": "<Fixed Frame>",
        "Plane Cell Count": 10,
        "Normal Cell Count": 0,
        "Cell Size": 1.0,
        "Line Style": "Lines",
        "Line Style/Line Width": 0.03,
        "Color": "160; 160; 164",
        "Alpha": 0.5,
        "Plane": "XY",
        **_OFFSET,
    },
    "rviz/RobotModel": {
        "Visual Enabled": True,
        "Collision Enabled": False,
        "Update Interval": 0.0,
        "Alpha": 1.0,
        "Robot Description": "robot_description",
        "TF Prefix": "",
    },
    "rviz/TF": {
        "Show Names": True,
        "Show Axes": True,
        "Show Arrows": True,
        "Marker Scale": 1.0,
        "Marker Alpha": 1.0,
        "Update Interval": 0.0,
        "Frame Timeout": 15.0,
        "Frames/All Enabled": True,
    },
    "rviz/LaserScan": _CLOUD,
    "rviz/PointCloud2": _CLOUD,
    "rviz/PointCloud": _CLOUD,
    "rviz/Map": {
        "Topic": "",
        "Unreliable": False,
        "Alpha": 0.7,
        "Color Scheme": "map",
        "Draw Behind": False,
        "Use Timestamp": False,
    },
    "rviz/Path": {
        **_SUBSCRIBER,
        "Line Style": "Lines",
        "Line Width": 0.03,
        "Color": "25; 255; 0",
        "Alpha": 1.0,
        "Buffer Length": 1,
        **_OFFSET,
        "Pose Style": "None",
        "Pose Color": "255; 85; 255",
        "Length": 0.3,
        "Radius": 0.03,
        "Head Diameter": 0.3,
        "Head Length": 0.2,
        "Shaft Diameter": 0.1,
        "Shaft Length": 0.1,
    },
    "rviz/PoseArray": {
        **_SUBSCRIBER,
        "Shape": "Arrow (Flat)",
        "Color": "255; 25; 0",
        "Alpha": 1.0,
        "Arrow Length": 0.3,
        "Head Radius": 0.03,
        "Head Length": 0.07,
        "Shaft Radius": 0.01,
        "Shaft Length": 0.23,
        "Axes Length": 0.3,
        "Axes Radius": 0.01,
    },
    "rviz/Odometry": {
        **_SUBSCRIBER,
        "Position Tolerance": 0.1,
        "Angle Tolerance": 0.1,
        "Keep": 100,
        **{("Shape" if k == "Shape" else f"Shape/{k}"): v for k, v in _ARROW.items()},
        **_COVARIANCE,
    },
    "rviz/Pose": {**_SUBSCRIBER, **_ARROW},
    "rviz/PoseWithCovariance": {**_SUBSCRIBER, **_ARROW, **_COVARIANCE},
    "rviz/Image": {
        "Image Topic": "",
        "Transport Hint": "raw",
        "Queue Size": 2,
        "Unreliable": False,
        "Normalize Range": True,
        "Min Value": 0.0,
        "Max Value": 1.0,
        "Median window": 5,
    },
    "rviz/Camera": {
        "Image Topic": "",
        "Transport Hint": "raw",
        "Queue Size": 2,
        "Unreliable": False,
        "Image Rendering": "background and overlay",
        "Overlay Alpha": 0.5,
        "Zoom Factor": 1.0,
        "Visibility": True,
    },
    "rviz/Marker": {"Marker Topic": "visualization_marker", "Queue Size": 100},
    "rviz/MarkerArray": {"Marker Topic": "visualization_marker_array", "Queue Size": 100},
    "rviz/Polygon": {**_SUBSCRIBER, "Color": "25; 255; 0", "Alpha": 1.0},
    "rviz/GridCells": {**_SUBSCRIBER, "Color": "25; 255; 0", "Alpha": 1.0},
    "rviz/PointStamped": {
        **_SUBSCRIBER,
        "Color": "204; 41; 204",
        "Alpha": 1.0,
        "Radius": 0.2,
        "History Length": 1,
    },
    "rviz/Range": {**_SUBSCRIBER, "Color": "255; 255; 255", "Alpha": 0.5, "Buffer Length": 1},
    "rviz/InteractiveMarkers": {
        "Update Topic": "",
        "Show Descriptions": True,
        "Show Axes": False,
        "Show Visual Aids": False,
        "Enable Transparency": True,
    },
    "rviz/Axes": {
        "Reference Frame": "<Fixed Frame>",
        "Length": 1.0,
        "Radius": 0.1,
        "Show Trail": False,
        "Alpha": 1.0,
    },
    GROUP: {},
}
"""rviz 1.14's default of every property of each display class (property paths joined by
``/``)."""

_VIEW_COMMON: Final[dict[str, Any]] = {
    "Target Frame": "<Fixed Frame>",
    "Near Clip Distance": 0.01,
    "Invert Z Axis": False,
}
_ORBIT: Final[dict[str, Any]] = {
    **_VIEW_COMMON,
    "Distance": 10.0,
    "Focal Point/X": 0.0,
    "Focal Point/Y": 0.0,
    "Focal Point/Z": 0.0,
    "Pitch": 0.785398,
    "Yaw": 0.785398,
    "Field of View": 0.785398,
    "Focal Shape Size": 0.05,
    "Focal Shape Fixed Size": True,
}
VIEW_DEFAULTS: dict[str, dict[str, Any]] = {
    "rviz/Orbit": _ORBIT,
    "rviz/XYOrbit": _ORBIT,
    "rviz/ThirdPersonFollower": _ORBIT,
    "rviz/TopDownOrtho": {**_VIEW_COMMON, "Scale": 10.0, "Angle": 0.0, "X": 0.0, "Y": 0.0},
    "rviz/FPS": {
        **_VIEW_COMMON,
        "Pitch": 0.0,
        "Yaw": 0.0,
        "Roll": 0.0,
        "Position/X": 0.0,
        "Position/Y": 0.0,
        "Position/Z": 0.0,
    },
}
"""rviz 1.14's default of every property of each view controller class."""

GLOBAL_DEFAULTS: dict[str, Any] = {
    "Fixed Frame": "map",
    "Background Color": "48; 48; 48",
    "Frame Rate": 30,
    "Default Light": True,
}
"""rviz 1.14's Global Options when a config sets none."""
