"""tf, as belvedere provides it to the scripts it runs (belvedere.ros1.tf)."""

from belvedere.ros1.tf import *  # noqa: F403
from belvedere.ros1.tf import __all__ as __all__

from . import transformations as transformations
