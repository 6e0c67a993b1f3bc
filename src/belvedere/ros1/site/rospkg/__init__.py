"""rospkg, as belvedere provides it (belvedere.ros1.rospkg)."""

from belvedere.ros1.rospkg import *  # noqa: F403
from belvedere.ros1.rospkg import __all__ as __all__
