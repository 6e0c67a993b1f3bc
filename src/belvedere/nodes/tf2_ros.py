"""tf2_ros: static_transform_publisher."""

from __future__ import annotations

from belvedere.nodes._registry import Starter, TransformClaim
from belvedere.nodes.tf import static_claim, static_publisher

__all__ = ["ANONYMOUS", "EXECUTABLES", "JOINING", "PACKAGE", "TRANSFORMS"]

PACKAGE = "tf2_ros"
EXECUTABLES: dict[str, Starter] = {"static_transform_publisher": static_publisher}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
ANONYMOUS = frozenset({"static_transform_publisher"})
"""Named as roscpp's ``AnonymousName`` names it when run without ``__name:=``."""
TRANSFORMS: dict[str, TransformClaim] = {"static_transform_publisher": static_claim}
