"""tf2_ros: static_transform_publisher."""

from __future__ import annotations

from belvedere.nodes._registry import Starter
from belvedere.nodes.tf import static_publisher

__all__ = ["EXECUTABLES", "PACKAGE"]

PACKAGE = "tf2_ros"
EXECUTABLES: dict[str, Starter] = {"static_transform_publisher": static_publisher}
