"""The browser viewer (rviz and joint_state_publisher_gui in any browser), built on viser."""

from belvedere.viewer._access import ViewerError, viewer_access
from belvedere.viewer._canvas import Canvas
from belvedere.viewer._catalog import DISPLAYS
from belvedere.viewer._display import Display
from belvedere.viewer._reconfigure import ReconfigurePage
from belvedere.viewer._robot import MeshAccessError, RobotDrawing, allowed_mesh_path
from belvedere.viewer._rqt_console import ConsolePage
from belvedere.viewer._rqt_image import ImagePage
from belvedere.viewer._rqt_plot import PlotPage
from belvedere.viewer._rviz import (
    RvizConfig,
    RvizDisplay,
    RvizView,
    format_color,
    parse_color,
    read_rviz,
    write_rviz,
)
from belvedere.viewer._tool_page import ToolPage
from belvedere.viewer._viewer import SimControls, Viewer
from belvedere.viewer._views import floor_point

__all__ = [
    "DISPLAYS",
    "Canvas",
    "ConsolePage",
    "Display",
    "ImagePage",
    "MeshAccessError",
    "PlotPage",
    "ReconfigurePage",
    "RobotDrawing",
    "RvizConfig",
    "RvizDisplay",
    "RvizView",
    "SimControls",
    "ToolPage",
    "Viewer",
    "ViewerError",
    "allowed_mesh_path",
    "floor_point",
    "format_color",
    "parse_color",
    "read_rviz",
    "viewer_access",
    "write_rviz",
]
