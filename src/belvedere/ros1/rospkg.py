"""The part of ``rospkg`` scripts use: ``RosPack().get_path(name)`` and friends, over
belvedere's package path (``ROS_PACKAGE_PATH``, ``BELVEDERE_PACKAGE_PATH``, the script's
workspace)."""

from __future__ import annotations

import sys
from pathlib import Path

from belvedere.errors import BelvedereError
from belvedere.packages import PackageIndex

__all__ = ["ResourceNotFound", "RosPack", "get_ros_package_path"]


class ResourceNotFound(Exception):  # noqa: N818 (rospkg's name)
    """A package that is not on the package path (``str()`` is its name, as rospkg's)."""

    def __init__(self, name: str, ros_paths: list[str] | None = None) -> None:
        super().__init__(name)
        self.ros_paths = ros_paths


def _index() -> PackageIndex:
    script = Path(sys.argv[0]).resolve() if sys.argv and sys.argv[0] else None
    return PackageIndex.from_environment(near=script if script and script.is_file() else None)


def get_ros_package_path() -> str:
    return ":".join(str(p) for p in _index().search_path)


class RosPack:
    """Finds packages as ``rospack`` does."""

    def __init__(self, ros_paths: list[str] | None = None) -> None:
        index = _index()
        if ros_paths is not None:
            index = PackageIndex([*(Path(p) for p in ros_paths), *index.search_path])
        self._index = index

    def get_path(self, name: str) -> str:
        try:
            return str(self._index.find(name))
        except BelvedereError:
            raise ResourceNotFound(name, [str(p) for p in self._index.search_path]) from None

    def list(self) -> list[str]:
        return sorted(self._index.packages())
