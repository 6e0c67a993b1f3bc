"""cv_bridge, as belvedere provides it to the scripts it runs (belvedere.ros1.cv_bridge)."""

from belvedere.ros1.cv_bridge import *  # noqa: F403
from belvedere.ros1.cv_bridge import __all__ as __all__
