"""Gazebo's named materials (``<material>Gazebo/Blue</material>``, ``<script><name>``) as RGBA.

The colours are the diffuse colours of Gazebo classic's ``gazebo.material`` script, which
worlds and ``<gazebo reference>`` blocks name instead of giving colours.
"""

from __future__ import annotations

from typing import Final, NamedTuple

__all__ = ["GAZEBO_MATERIALS", "MaterialColours", "gazebo_material_colours", "gazebo_material_rgba"]

RGBA = tuple[float, float, float, float]


class MaterialColours(NamedTuple):
    """A material's colours for Phong shading (OGRE's ``ambient``/``diffuse``/``specular``)."""

    ambient: RGBA
    diffuse: RGBA
    specular: RGBA
    shininess: float = 0.0


GAZEBO_MATERIALS: Final[dict[str, RGBA]] = {
    "Gazebo/Grey": (0.7, 0.7, 0.7, 1.0),
    "Gazebo/Gray": (0.7, 0.7, 0.7, 1.0),
    "Gazebo/DarkGrey": (0.35, 0.35, 0.35, 1.0),
    "Gazebo/DarkGray": (0.35, 0.35, 0.35, 1.0),
    "Gazebo/LightGrey": (0.85, 0.85, 0.85, 1.0),
    "Gazebo/White": (1.0, 1.0, 1.0, 1.0),
    "Gazebo/FlatBlack": (0.1, 0.1, 0.1, 1.0),
    "Gazebo/Black": (0.1, 0.1, 0.1, 1.0),
    "Gazebo/Red": (1.0, 0.0, 0.0, 1.0),
    "Gazebo/RedBright": (0.87, 0.26, 0.07, 1.0),
    "Gazebo/Green": (0.0, 0.8, 0.0, 1.0),
    "Gazebo/Blue": (0.0, 0.0, 0.8, 1.0),
    "Gazebo/SkyBlue": (0.53, 0.81, 0.92, 1.0),
    "Gazebo/Yellow": (1.0, 1.0, 0.0, 1.0),
    "Gazebo/Orange": (1.0, 0.5, 0.0, 1.0),
    "Gazebo/Purple": (0.5, 0.0, 1.0, 1.0),
    "Gazebo/Turquoise": (0.0, 0.8, 0.8, 1.0),
    "Gazebo/ZincYellow": (0.9725, 0.9529, 0.2078, 1.0),
    "Gazebo/Indigo": (0.33, 0.0, 0.5, 1.0),
    "Gazebo/Wood": (0.6, 0.4, 0.2, 1.0),
    "Gazebo/WoodFloor": (0.6, 0.45, 0.3, 1.0),
    "Gazebo/WoodPallet": (0.6, 0.45, 0.3, 1.0),
    "Gazebo/CeilingTiled": (0.9, 0.9, 0.9, 1.0),
    "Gazebo/Bricks": (0.6, 0.3, 0.2, 1.0),
    "Gazebo/Road": (0.3, 0.3, 0.3, 1.0),
    "Gazebo/Residential": (0.8, 0.75, 0.7, 1.0),
    "Gazebo/Grass": (0.3, 0.6, 0.2, 1.0),
    "Gazebo/GreyTransparent": (0.5, 0.5, 0.5, 0.5),
    "Gazebo/BlueTransparent": (0.0, 0.0, 1.0, 0.5),
    "Gazebo/RedTransparent": (1.0, 0.0, 0.0, 0.5),
    "Gazebo/GreenTransparent": (0.0, 1.0, 0.0, 0.5),
}


_SHADING: Final[dict[str, MaterialColours]] = {
    "Gazebo/Grey": MaterialColours(
        (0.3, 0.3, 0.3, 1.0), (0.7, 0.7, 0.7, 1.0), (0.01, 0.01, 0.01, 1.0), 1.5
    ),
    "Gazebo/Red": MaterialColours(
        (1.0, 0.0, 0.0, 1.0), (1.0, 0.0, 0.0, 1.0), (0.1, 0.1, 0.1, 1.0), 1.0
    ),
}
_SHADING["Gazebo/Gray"] = _SHADING["Gazebo/Grey"]
_DEFAULT_SPECULAR: Final[RGBA] = (0.1, 0.1, 0.1, 1.0)


def gazebo_material_colours(name: str | None) -> MaterialColours | None:
    """The shading colours of a Gazebo material name (None if unknown): the script's own
    where they are written here, else its diffuse colour as ambient too and a faint
    specular, as most of ``gazebo.material`` has."""
    rgba = gazebo_material_rgba(name)
    if rgba is None or name is None:
        return None
    known = _SHADING.get(name.strip())
    return known or MaterialColours(rgba, rgba, _DEFAULT_SPECULAR, 1.0)


def gazebo_material_rgba(name: str | None) -> RGBA | None:
    """The colour of a Gazebo material name (None if unknown)."""
    if not name:
        return None
    return GAZEBO_MATERIALS.get(name.strip())
