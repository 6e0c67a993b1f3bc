"""dynamic_reconfigure.client (belvedere.ros1.dynamic_reconfigure.client)."""

from belvedere.ros1.dynamic_reconfigure.client import *  # noqa: F403
from belvedere.ros1.dynamic_reconfigure.client import __all__ as __all__
