"""The part of ``roslib`` scripts still call: ``load_manifest`` (a no-op since catkin) and
``roslib.packages.get_pkg_dir``."""

from __future__ import annotations

from types import SimpleNamespace

from belvedere.ros1.rospkg import RosPack

__all__ = ["load_manifest", "packages"]


def load_manifest(package_name: str, bootstrap_version: str = "0.7") -> None:
    """Nothing to do: catkin packages are on the path already (as in ROS since Groovy)."""


def _get_pkg_dir(package: str, required: bool = True, ros_root: str | None = None) -> str:
    return RosPack().get_path(package)


packages = SimpleNamespace(get_pkg_dir=_get_pkg_dir)
"""``roslib.packages``"""
