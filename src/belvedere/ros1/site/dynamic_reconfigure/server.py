"""dynamic_reconfigure.server (belvedere.ros1.dynamic_reconfigure.server)."""

from belvedere.ros1.dynamic_reconfigure.server import *  # noqa: F403
from belvedere.ros1.dynamic_reconfigure.server import __all__ as __all__
