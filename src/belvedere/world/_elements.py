"""Reading the small SDF elements: numbers, flags, surfaces, materials."""

from __future__ import annotations

import math
import sys

from belvedere.description.gazebo_materials import gazebo_material_colours
from belvedere.description.urdf import GazeboPlugin, Source, XmlData
from belvedere.world._model import RGBA, Material, SDFError, Surface
from belvedere.xmldom import CData, Element, Text

__all__ = [
    "child",
    "flag",
    "floats",
    "number",
    "plugin",
    "positive",
    "read_material",
    "read_surface",
    "xml_data",
]


def xml_data(el: Element) -> XmlData:
    """An element kept as data (a sensor, a plugin's parameters), with its line."""
    return XmlData(
        el.tag,
        tuple(el.attrs.items()),
        "".join(c.data for c in el.children() if isinstance(c, Text | CData)),
        tuple(xml_data(c) for c in el.elements()),
        Source(el.loc),
    )


def plugin(el: Element) -> GazeboPlugin:
    """A ``<plugin filename=… name=…>`` and its parameters."""
    return GazeboPlugin(
        el.attrs.get("name", ""),
        el.attrs.get("filename", ""),
        tuple(xml_data(c) for c in el.elements()),
        Source(el.loc),
    )


def floats(el: Element, count: int | None = None) -> tuple[float, ...]:
    text = el.text_content().split()
    try:
        values = tuple(float(v) for v in text)
    except ValueError:
        msg = f"<{el.tag}> expects numbers, got {el.text_content().strip()!r}"
        raise SDFError(msg, el.loc) from None
    for token, value in zip(text, values, strict=True):
        if not math.isfinite(value):
            msg = f"<{el.tag}> expects finite numbers, got {token!r}"
            raise SDFError(msg, el.loc, hint=f"the largest double is ±{sys.float_info.max:.17g}")
    if count is not None and len(values) != count:
        msg = f"<{el.tag}> expects {count} numbers, got {len(values)}"
        raise SDFError(msg, el.loc)
    return values


def child(el: Element, tag: str) -> Element | None:
    return next((c for c in el.elements() if c.tag == tag), None)


def number(el: Element, tag: str, default: float) -> float:
    c = child(el, tag)
    return floats(c, 1)[0] if c is not None else default


def positive(el: Element, tag: str, default: float) -> float:
    value = number(el, tag, default)
    if not value > 0:
        msg = f"<{tag}> must be positive, got {value}"
        raise SDFError(msg, (child(el, tag) or el).loc)
    return value


def flag(el: Element, tag: str, default: bool) -> bool:
    c = child(el, tag)
    if c is None:
        return default
    text = c.text_content().strip().lower()
    if text in ("1", "true"):
        return True
    if text in ("0", "false"):
        return False
    msg = f"<{tag}> expects true or false, got {text!r}"
    raise SDFError(msg, c.loc)


def read_surface(el: Element | None) -> Surface | None:
    if el is None:
        return None
    friction = child(el, "friction")
    ode = child(friction, "ode") if friction is not None else None
    contact = child(el, "contact")
    contact_ode = child(contact, "ode") if contact is not None else None

    def opt(parent: Element | None, tag: str) -> float | None:
        c = child(parent, tag) if parent is not None else None
        return floats(c, 1)[0] if c is not None else None

    mu, mu2 = opt(ode, "mu"), opt(ode, "mu2")
    return Surface(
        mu=1.0 if mu is None else mu,
        mu2=1.0 if mu2 is None else mu2,
        kp=opt(contact_ode, "kp"),
        kd=opt(contact_ode, "kd"),
        min_depth=opt(contact_ode, "min_depth"),
        max_vel=opt(contact_ode, "max_vel"),
    )


def read_colour(el: Element | None, default: RGBA) -> RGBA:
    """An SDF colour: 3 or 4 numbers (alpha 1 when left out)."""
    if el is None:
        return default
    v = floats(el)
    if len(v) not in (3, 4):
        msg = f"<{el.tag}> expects a colour (r g b [a]), got {el.text_content().strip()!r}"
        raise SDFError(msg, el.loc)
    return (v[0], v[1], v[2], v[3] if len(v) > 3 else 1.0)


def read_material(el: Element | None) -> Material | None:
    """A visual's ``<material>``: a Gazebo script name's colours, overridden by the
    colours written out (a missing ambient is the diffuse colour, as sdformat's URDF
    conversion writes both)."""
    if el is None:
        return None
    script = child(el, "script")
    name_el = child(script, "name") if script is not None else None
    named = gazebo_material_colours(name_el.text_content()) if name_el is not None else None
    given = {
        tag: read_colour(c, (0.0, 0.0, 0.0, 1.0))
        for tag in ("ambient", "diffuse", "specular", "emissive")
        if (c := child(el, tag)) is not None
    }
    if named is None and not given:
        return None
    diffuse = given.get("diffuse") or (named.diffuse if named else None)
    ambient = given.get("ambient") or (named.ambient if named else None)
    diffuse = diffuse or ambient or (1.0, 1.0, 1.0, 1.0)
    shininess = child(el, "shininess")
    return Material(
        ambient=ambient or diffuse,
        diffuse=diffuse,
        specular=given.get("specular") or (named.specular if named else (0.0, 0.0, 0.0, 1.0)),
        emissive=given.get("emissive", (0.0, 0.0, 0.0, 1.0)),
        shininess=floats(shininess, 1)[0]
        if shininess is not None
        else (named.shininess if named else 0.0),
    )
