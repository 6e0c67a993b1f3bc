"""dynamic_reconfigure.dynparam (belvedere.ros1.dynamic_reconfigure.dynparam)."""

from belvedere.ros1.dynamic_reconfigure.dynparam import *  # noqa: F403
from belvedere.ros1.dynamic_reconfigure.dynparam import __all__ as __all__
