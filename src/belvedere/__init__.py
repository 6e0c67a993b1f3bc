"""belvedere: the classic ROS robot-modelling and simulation workflow, with no ROS to install."""

__version__ = "0.1.0"

__all__ = ["__version__"]
