"""roslaunch: the course's launch files, read (``load_launch``) and run on one graph."""

from belvedere.launch._loader import load_launch
from belvedere.launch._model import LaunchConfig, LaunchError, LaunchNode, LaunchParam

__all__ = ["LaunchConfig", "LaunchError", "LaunchNode", "LaunchParam", "load_launch"]
