"""rostest, as belvedere provides it to the scripts it runs (belvedere.ros1.rostest)."""

from belvedere.ros1.rostest import *  # noqa: F403
from belvedere.ros1.rostest import __all__ as __all__
