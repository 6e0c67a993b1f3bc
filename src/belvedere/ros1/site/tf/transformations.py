"""tf.transformations (belvedere.ros1.transformations)."""

from belvedere.ros1.transformations import *  # noqa: F403
from belvedere.ros1.transformations import _AXES2TUPLE as _AXES2TUPLE
from belvedere.ros1.transformations import _EPS as _EPS
from belvedere.ros1.transformations import _NEXT_AXIS as _NEXT_AXIS
from belvedere.ros1.transformations import _TUPLE2AXES as _TUPLE2AXES
from belvedere.ros1.transformations import __all__ as __all__
