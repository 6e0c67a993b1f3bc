"""Names the physics simulation offers, for tools that must not load the physics to use
them (the viewer, ``belvedere world``)."""

from typing import Final

__all__ = ["SAVE_WORLD", "SAVE_WORLD_TYPE"]

SAVE_WORLD: Final = "/gazebo/save_world"
"""Writes the simulated world, as it is now, to the ``.world`` file the request names."""
SAVE_WORLD_TYPE: Final = "belvedere_msgs/SaveWorld"
