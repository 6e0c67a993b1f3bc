"""dynamic_reconfigure, as belvedere provides it to the scripts it runs
(belvedere.ros1.dynamic_reconfigure)."""

from belvedere.ros1.dynamic_reconfigure import *  # noqa: F403
from belvedere.ros1.dynamic_reconfigure import __all__ as __all__
