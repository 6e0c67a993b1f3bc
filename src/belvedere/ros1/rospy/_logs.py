"""rospy's ``logdebug`` … ``logfatal`` and their ``_throttle``, ``_throttle_identical`` and
``_once`` variants (each call site throttled on its own, as rospy does)."""

from __future__ import annotations

from typing import Any

from belvedere.ros1.rospy._logging import (
    DEBUG,
    ERROR,
    FATAL,
    INFO,
    WARN,
    log,
    log_once,
    log_throttle,
    log_throttle_identical,
)

__all__ = [
    "logdebug",
    "logdebug_once",
    "logdebug_throttle",
    "logdebug_throttle_identical",
    "logerr",
    "logerr_once",
    "logerr_throttle",
    "logerr_throttle_identical",
    "logfatal",
    "logfatal_once",
    "logfatal_throttle",
    "logfatal_throttle_identical",
    "loginfo",
    "loginfo_once",
    "loginfo_throttle",
    "loginfo_throttle_identical",
    "logout",
    "logwarn",
    "logwarn_once",
    "logwarn_throttle",
    "logwarn_throttle_identical",
]


def logdebug(msg: Any, *args: Any, **kwargs: Any) -> None:
    log(DEBUG, msg, args, depth=2)


def logdebug_throttle(period: float, msg: Any, *args: Any, **kwargs: Any) -> None:
    log_throttle(period, DEBUG, msg, args)


def logdebug_throttle_identical(period: float, msg: Any, *args: Any, **kwargs: Any) -> None:
    log_throttle_identical(period, DEBUG, msg, args)


def logdebug_once(msg: Any, *args: Any, **kwargs: Any) -> None:
    log_once(DEBUG, msg, args)


def loginfo(msg: Any, *args: Any, **kwargs: Any) -> None:
    log(INFO, msg, args, depth=2)


def loginfo_throttle(period: float, msg: Any, *args: Any, **kwargs: Any) -> None:
    log_throttle(period, INFO, msg, args)


def loginfo_throttle_identical(period: float, msg: Any, *args: Any, **kwargs: Any) -> None:
    log_throttle_identical(period, INFO, msg, args)


def loginfo_once(msg: Any, *args: Any, **kwargs: Any) -> None:
    log_once(INFO, msg, args)


def logwarn(msg: Any, *args: Any, **kwargs: Any) -> None:
    log(WARN, msg, args, depth=2)


def logwarn_throttle(period: float, msg: Any, *args: Any, **kwargs: Any) -> None:
    log_throttle(period, WARN, msg, args)


def logwarn_throttle_identical(period: float, msg: Any, *args: Any, **kwargs: Any) -> None:
    log_throttle_identical(period, WARN, msg, args)


def logwarn_once(msg: Any, *args: Any, **kwargs: Any) -> None:
    log_once(WARN, msg, args)


def logerr(msg: Any, *args: Any, **kwargs: Any) -> None:
    log(ERROR, msg, args, depth=2)


def logerr_throttle(period: float, msg: Any, *args: Any, **kwargs: Any) -> None:
    log_throttle(period, ERROR, msg, args)


def logerr_throttle_identical(period: float, msg: Any, *args: Any, **kwargs: Any) -> None:
    log_throttle_identical(period, ERROR, msg, args)


def logerr_once(msg: Any, *args: Any, **kwargs: Any) -> None:
    log_once(ERROR, msg, args)


def logfatal(msg: Any, *args: Any, **kwargs: Any) -> None:
    log(FATAL, msg, args, depth=2)


def logfatal_throttle(period: float, msg: Any, *args: Any, **kwargs: Any) -> None:
    log_throttle(period, FATAL, msg, args)


def logfatal_throttle_identical(period: float, msg: Any, *args: Any, **kwargs: Any) -> None:
    log_throttle_identical(period, FATAL, msg, args)


def logfatal_once(msg: Any, *args: Any, **kwargs: Any) -> None:
    log_once(FATAL, msg, args)


logout = loginfo
