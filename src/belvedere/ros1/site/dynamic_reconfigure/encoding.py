"""dynamic_reconfigure.encoding (belvedere.ros1.dynamic_reconfigure._encoding)."""

from belvedere.ros1.dynamic_reconfigure._encoding import Config as Config
from belvedere.ros1.dynamic_reconfigure._encoding import extract_params as extract_params

__all__ = ["Config", "extract_params"]
