"""The TF buffer's errors, as tf2's exceptions."""

from __future__ import annotations

from belvedere.errors import BelvedereError

__all__ = [
    "TFConnectivityError",
    "TFError",
    "TFExtrapolationError",
    "TFInvalidArgumentError",
    "TFLookupError",
]


class TFError(BelvedereError):
    """A transform that cannot be looked up or stored (tf2's ``TransformException``)."""


class TFLookupError(TFError):
    """An unknown frame, or a tree with a loop (tf2's ``LookupException``)."""


class TFConnectivityError(TFError):
    """Frames in different trees (tf2's ``ConnectivityException``)."""


class TFExtrapolationError(TFError):
    """No data at the time asked for (tf2's ``ExtrapolationException``)."""


class TFInvalidArgumentError(TFError):
    """A frame name tf2 refuses: empty, or with a leading ``/``."""
