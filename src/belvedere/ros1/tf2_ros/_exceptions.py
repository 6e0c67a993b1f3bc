"""tf2's exception classes, named as tf2's python binding names them (``tf2.LookupException``
in a traceback), and :class:`belvedere.tf.TFBuffer`'s errors translated into them."""

from __future__ import annotations

from belvedere.tf import (
    TFConnectivityError,
    TFError,
    TFExtrapolationError,
    TFInvalidArgumentError,
    TFLookupError,
)

__all__ = [
    "ConnectivityException",
    "ExtrapolationException",
    "InvalidArgumentException",
    "LookupException",
    "NotImplementedException",
    "TimeoutException",
    "TransformException",
    "TypeException",
    "translated",
]


class TransformException(Exception):  # noqa: N818 (tf2's name)
    """Any failure to transform (``tf.Exception`` in tf)."""

    __module__ = "tf2"


class LookupException(TransformException):
    """An unknown frame."""

    __module__ = "tf2"


class ConnectivityException(TransformException):
    """Frames that are not in the same tree."""

    __module__ = "tf2"


class ExtrapolationException(TransformException):
    """No data at the time asked for."""

    __module__ = "tf2"


class InvalidArgumentException(TransformException):
    """A frame name tf2 refuses (empty, or starting with ``/``)."""

    __module__ = "tf2"


class TimeoutException(TransformException):
    """Part of tf2's interface; tf2_ros's python buffer never raises it."""

    __module__ = "tf2"


class TypeException(Exception):  # noqa: N818 (tf2_ros's name)
    """A type :meth:`Buffer.transform` cannot handle (its ``tf2_*`` module not imported)."""

    def __init__(self, errstr: str) -> None:
        super().__init__(errstr)
        self.errstr = errstr


class NotImplementedException(Exception):  # noqa: N818 (tf2_ros's name)
    """A buffer interface method its subclass does not implement."""

    def __init__(self) -> None:
        self.errstr = "CanTransform or LookupTransform not implemented"
        super().__init__()


_CLASSES: dict[type[TFError], type[TransformException]] = {
    TFLookupError: LookupException,
    TFConnectivityError: ConnectivityException,
    TFExtrapolationError: ExtrapolationException,
    TFInvalidArgumentError: InvalidArgumentException,
}


def translated(err: TFError) -> TransformException:
    """The tf2 exception for an error of belvedere's buffer, with the same text."""
    return _CLASSES.get(type(err), TransformException)(err.message)
