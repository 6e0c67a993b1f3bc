"""A world's ``<physics>``, ``<scene>`` and ``<light>``s."""

from __future__ import annotations

from belvedere.world._elements import child as _child
from belvedere.world._elements import flag as _flag
from belvedere.world._elements import floats as _floats
from belvedere.world._elements import number as _number
from belvedere.world._elements import positive as _positive
from belvedere.world._elements import read_colour
from belvedere.world._model import Attenuation, Light, Physics, Scene
from belvedere.world._sdf._scope import ElementReader
from belvedere.xmldom import Element

__all__ = ["EnvironmentReader"]


class EnvironmentReader(ElementReader):
    """What a world has besides its models."""

    def scene(self, el: Element | None) -> Scene:
        """``<scene>``: ambient light, background colour, shadows (off unless asked for)."""
        if el is None:
            return Scene()
        default = Scene()
        return Scene(
            ambient=read_colour(_child(el, "ambient"), default.ambient),
            background=read_colour(_child(el, "background"), default.background),
            shadows=_flag(el, "shadows", default.shadows),
        )

    def physics(self, world_el: Element) -> Physics:
        physics_el = _child(world_el, "physics")
        gravity = (0.0, 0.0, -9.8)
        for holder in (physics_el, world_el):  # 1.4 keeps gravity inside <physics>
            g = _child(holder, "gravity") if holder is not None else None
            if g is not None:
                x, y, z = _floats(g, 3)
                gravity = (x, y, z)
        if physics_el is None:
            return Physics(gravity=gravity)
        step = _positive(physics_el, "max_step_size", 0.001)
        return Physics(
            max_step_size=step,
            real_time_update_rate=_number(physics_el, "real_time_update_rate", 1000.0),
            real_time_factor=_number(physics_el, "real_time_factor", 1.0),
            gravity=gravity,
        )

    def light(self, el: Element) -> Light:
        pose, _ = self.pose(el)
        direction = _child(el, "direction")
        v = _floats(direction, 3) if direction is not None else (-0.5, 0.1, -0.9)
        attenuation = _child(el, "attenuation")
        fall = Attenuation()
        if attenuation is not None:
            fall = Attenuation(
                range=_number(attenuation, "range", fall.range),
                constant=_number(attenuation, "constant", fall.constant),
                linear=_number(attenuation, "linear", fall.linear),
                quadratic=_number(attenuation, "quadratic", fall.quadratic),
            )
        spot = _child(el, "spot")
        return Light(
            name=el.attrs.get("name", "light"),
            type=el.attrs.get("type", "point"),
            pose=pose,
            diffuse=read_colour(_child(el, "diffuse"), (0.8, 0.8, 0.8, 1.0)),
            direction=(v[0], v[1], v[2]),
            cast_shadows=_flag(el, "cast_shadows", False),
            specular=read_colour(_child(el, "specular"), (0.1, 0.1, 0.1, 1.0)),
            attenuation=fall,
            spot_inner_angle=_number(spot, "inner_angle", 0.0) if spot is not None else 0.0,
            spot_outer_angle=_number(spot, "outer_angle", 0.0) if spot is not None else 0.0,
            spot_falloff=_number(spot, "falloff", 0.0) if spot is not None else 0.0,
            source=el.loc,
        )
