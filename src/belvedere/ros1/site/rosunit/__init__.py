"""rosunit, as belvedere provides it to the scripts it runs (belvedere.ros1.rosunit)."""

from belvedere.ros1.rosunit import *  # noqa: F403
from belvedere.ros1.rosunit import __all__ as __all__
