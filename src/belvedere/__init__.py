"""belvedere: the classic ROS robot-modelling and simulation workflow, with no ROS to install."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("belvedere")
except PackageNotFoundError:  # running from a source tree without installing
    __version__ = "0.0.0"

__all__ = ["__version__"]
