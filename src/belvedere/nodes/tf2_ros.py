"""tf2_ros: static_transform_publisher."""

from __future__ import annotations

from belvedere.nodes._registry import Starter, TransformClaim
from belvedere.nodes.tf import static_claim, static_publisher

__all__ = ["EXECUTABLES", "PACKAGE", "TRANSFORMS"]

PACKAGE = "tf2_ros"
EXECUTABLES: dict[str, Starter] = {"static_transform_publisher": static_publisher}
TRANSFORMS: dict[str, TransformClaim] = {"static_transform_publisher": static_claim}
