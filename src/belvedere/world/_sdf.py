"""Reading SDF 1.4 to 1.9: ``.world`` files and ``model.sdf`` into a :class:`WorldModel`.

Handled: ``<physics>`` (and 1.4's gravity inside it), models (static or not) with links,
inertials, collisions, visuals, joints, nested models and frames; geometry box, cylinder,
sphere, plane, mesh, polyline; poses with ``relative_to``/``frame``, ``degrees`` and
quaternions; ``<include>`` of ``model://`` (with ``<name>``, ``<pose>``, ``<static>``);
the ``<state>`` block Gazebo writes when it saves a world; lights. What is not simulated
(actors, populations, heightmaps, world plugins) is a warning naming its line.
"""

from __future__ import annotations

import math
import os
import sys
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

from belvedere.description.gazebo_materials import gazebo_material_colours
from belvedere.description.urdf import Box, Cylinder, Inertial, Mesh, Pose, Sphere
from belvedere.errors import SourceLocation
from belvedere.packages import PackageIndex
from belvedere.world._frames import Frame, resolve_frames
from belvedere.world._model import (
    RGBA,
    Attenuation,
    Light,
    Material,
    Physics,
    Plane,
    Polyline,
    Scene,
    SDFError,
    Shape,
    Surface,
    WorldGeometry,
    WorldJoint,
    WorldLink,
    WorldModel,
    WorldModelEntry,
)
from belvedere.world._paths import BUILTIN_MODELS, ModelPaths, model_sdf_file
from belvedere.world._poses import compose, from_matrix, inverse, matrix, quat_xyzw_to_rpy
from belvedere.xmldom import Element, parse_file, parse_string

__all__ = ["SDFError", "empty_world", "read_world", "read_world_string"]

EMPTY_WORLD = """<sdf version="1.6"><world name="default">
  <include><uri>model://ground_plane</uri></include>
  <include><uri>model://sun</uri></include>
</world></sdf>"""

_IGNORED_WORLD = {"scene", "gui", "spherical_coordinates", "magnetic_field", "atmosphere", "wind"}
_IGNORED_WORLD |= {"audio", "gravity", "physics", "model", "include", "light", "state", "plugin"}
_UNSUPPORTED = {"actor", "population", "road"}


def read_world(
    path: str | Path,
    *,
    packages: PackageIndex | None = None,
    model_paths: ModelPaths | None = None,
) -> WorldModel:
    """Read a ``.world`` (or a model ``.sdf``, which becomes a world holding that model)."""
    doc = parse_file(path, namespaces=False, keep_blank=False)
    return _Reader(_paths(packages, model_paths), str(path)).world(doc.root)


def read_world_string(
    text: str,
    path: str = "<string>",
    *,
    packages: PackageIndex | None = None,
    model_paths: ModelPaths | None = None,
) -> WorldModel:
    doc = parse_string(text, path, namespaces=False, keep_blank=False)
    return _Reader(_paths(packages, model_paths), path).world(doc.root)


def empty_world(*, model_paths: ModelPaths | None = None) -> WorldModel:
    """gazebo_ros's ``empty.world``: a ground plane and the sun (built in unless installed)."""
    return read_world_string(EMPTY_WORLD, "<empty world>", model_paths=model_paths)


def _paths(packages: PackageIndex | None, model_paths: ModelPaths | None) -> ModelPaths:
    return model_paths or ModelPaths.from_environment(packages=packages)


def _floats(el: Element, count: int | None = None) -> tuple[float, ...]:
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


def _child(el: Element, tag: str) -> Element | None:
    return next((c for c in el.elements() if c.tag == tag), None)


def _number(el: Element, tag: str, default: float) -> float:
    c = _child(el, tag)
    return _floats(c, 1)[0] if c is not None else default


def _positive(el: Element, tag: str, default: float) -> float:
    value = _number(el, tag, default)
    if not value > 0:
        msg = f"<{tag}> must be positive, got {value}"
        raise SDFError(msg, (_child(el, tag) or el).loc)
    return value


def _flag(el: Element, tag: str, default: bool) -> bool:
    c = _child(el, tag)
    if c is None:
        return default
    text = c.text_content().strip().lower()
    if text in ("1", "true"):
        return True
    if text in ("0", "false"):
        return False
    msg = f"<{tag}> expects true or false, got {text!r}"
    raise SDFError(msg, c.loc)


def _unique_names(kind: str, model: str, parts: list[WorldLink] | list[WorldJoint]) -> None:
    """SDF names siblings uniquely; a copied link would otherwise be simulated twice."""
    seen: dict[str, SourceLocation | None] = {}
    for part in parts:
        if part.name in seen:
            first = seen[part.name]
            msg = f"two {kind}s of model {model!r} are named {part.name!r} (the first at {first})"
            raise SDFError(msg, part.source)
        seen[part.name] = part.source


class _Reader:
    def __init__(self, model_paths: ModelPaths, path: str) -> None:
        self.paths = model_paths
        self.path = path
        self.version = "1.6"
        self.warnings: list[str] = []
        self.including: list[str] = []

    def warn(self, where: SourceLocation | None, text: str) -> None:
        self.warnings.append(f"{where or self.path}: warning: {text}")

    # --- poses ----------------------------------------------------------------------------------
    def pose(self, parent: Element) -> tuple[Pose, str | None]:
        el = _child(parent, "pose")
        if el is None:
            return Pose(), None
        relative_to = el.attrs.get("relative_to") or el.attrs.get("frame") or None
        degrees = el.attrs.get("degrees", "false").strip().lower() in ("1", "true")
        values = _floats(el)
        if el.attrs.get("rotation_format") == "quat_xyzw" or len(values) == 7:
            if len(values) != 7:
                msg = "a quat_xyzw <pose> needs 7 numbers: x y z qx qy qz qw"
                raise SDFError(msg, el.loc)
            rpy = quat_xyzw_to_rpy(*values[3:])
        elif len(values) == 6:
            r, p, y = values[3:6]
            rpy = (math.radians(r), math.radians(p), math.radians(y)) if degrees else (r, p, y)
        else:
            msg = f"<pose> expects 6 numbers (x y z roll pitch yaw), got {len(values)}"
            raise SDFError(msg, el.loc)
        return Pose((values[0], values[1], values[2]), (rpy[0], rpy[1], rpy[2])), relative_to

    # --- world ----------------------------------------------------------------------------------
    def world(self, root: Element) -> WorldModel:
        if root.tag != "sdf":
            msg = f"expected an <sdf> document, found <{root.tag}>"
            raise SDFError(msg, root.loc, hint="Gazebo classic worlds start with <sdf version=…>")
        self.version = root.attrs.get("version", "1.6")
        world_el = _child(root, "world")
        if world_el is None:
            alone = [self.model(m, Pose()) for m in root.elements() if m.tag == "model"]
            if not alone:
                msg = "no <world> or <model> in this SDF file"
                raise SDFError(msg, root.loc)
            self._unique(alone)
            return WorldModel(
                models=tuple(alone),
                path=self.path,
                sdf_version=self.version,
                warnings=tuple(self.warnings),
            )
        models: list[WorldModelEntry] = []
        lights: list[Light] = []
        for el in world_el.elements():
            if el.tag == "model":
                models.append(self.model(el, Pose()))
            elif el.tag == "include":
                included = self.include(el)
                if isinstance(included, Light):
                    lights.append(included)
                elif included is not None:
                    models.append(included)
            elif el.tag == "light":
                lights.append(self.light(el))
            elif el.tag in _UNSUPPORTED:
                self.warn(el.loc, f"<{el.tag}> is not simulated; ignored")
            elif el.tag == "plugin":
                name = el.attrs.get("filename", "?")
                if "gazebo_ros_api" not in name and "gazebo_ros_state" not in name:
                    self.warn(el.loc, f"world plugin {name!r} is not supported; ignored")
        models = self._relative_models(world_el, models)
        models = self.apply_state(world_el, models)
        self._unique(models)
        return WorldModel(
            name=world_el.attrs.get("name", "default"),
            physics=self.physics(world_el),
            models=tuple(models),
            lights=tuple(lights),
            scene=self.scene(_child(world_el, "scene")),
            path=self.path,
            sdf_version=self.version,
            warnings=tuple(self.warnings),
        )

    def scene(self, el: Element | None) -> Scene:
        """``<scene>``: ambient light, background colour, shadows (off unless asked for)."""
        if el is None:
            return Scene()
        default = Scene()
        return Scene(
            ambient=self.colour(_child(el, "ambient"), default.ambient),
            background=self.colour(_child(el, "background"), default.background),
            shadows=_flag(el, "shadows", default.shadows),
        )

    def colour(self, el: Element | None, default: RGBA) -> RGBA:
        """An SDF colour: 3 or 4 numbers (alpha 1 when left out)."""
        if el is None:
            return default
        v = _floats(el)
        if len(v) not in (3, 4):
            msg = f"<{el.tag}> expects a colour (r g b [a]), got {el.text_content().strip()!r}"
            raise SDFError(msg, el.loc)
        return (v[0], v[1], v[2], v[3] if len(v) > 3 else 1.0)

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
            diffuse=self.colour(_child(el, "diffuse"), (0.8, 0.8, 0.8, 1.0)),
            direction=(v[0], v[1], v[2]),
            cast_shadows=_flag(el, "cast_shadows", False),
            specular=self.colour(_child(el, "specular"), (0.1, 0.1, 0.1, 1.0)),
            attenuation=fall,
            spot_inner_angle=_number(spot, "inner_angle", 0.0) if spot is not None else 0.0,
            spot_outer_angle=_number(spot, "outer_angle", 0.0) if spot is not None else 0.0,
            spot_falloff=_number(spot, "falloff", 0.0) if spot is not None else 0.0,
            source=el.loc,
        )

    # --- includes ---------------------------------------------------------------------------------
    def include(self, el: Element) -> WorldModelEntry | Light | None:
        uri_el = _child(el, "uri")
        if uri_el is None:
            msg = "<include> needs a <uri>"
            raise SDFError(msg, el.loc)
        uri = uri_el.text_content().strip()
        name = uri.removeprefix("model://").strip("/")
        if not uri.startswith("model://"):
            path = Path(uri.removeprefix("file://"))
            if not path.is_absolute():
                path = Path(self.path).parent / path
            directory: Path | None = path if os.path.isdir(path) else None
        else:
            directory = self.paths.find(name)
        if directory is None:
            if name in BUILTIN_MODELS:
                return self.builtin(name, el)
            msg = f"model {uri!r} not found (searched: {self.paths.searched()})"
            raise SDFError(
                msg,
                uri_el.loc,
                hint="put the model under ~/.gazebo/models or a GAZEBO_MODEL_PATH directory; "
                "belvedere never downloads models",
            )
        sdf_file = model_sdf_file(directory)
        key = str(sdf_file.resolve())
        if key in self.including:
            msg = f"include cycle: {uri} includes itself"
            raise SDFError(msg, uri_el.loc)
        if not os.path.isfile(sdf_file):
            msg = f"model {uri!r}: {sdf_file} does not exist"
            raise SDFError(msg, uri_el.loc)
        self.including.append(key)
        try:
            doc = parse_file(sdf_file, namespaces=False, keep_blank=False)
            inner = _Reader(self.paths, str(sdf_file))
            inner.including = self.including
            inner.version = doc.root.attrs.get("version", self.version)
            model_el = _child(doc.root, "model")
            light_el = _child(doc.root, "light")
            if model_el is None and light_el is not None:
                return inner.light(light_el)
            if model_el is None:
                msg = f"{sdf_file} has no <model>"
                raise SDFError(msg, doc.root.loc)
            model = inner.model(model_el, Pose())
            self.warnings += inner.warnings
        finally:
            self.including.pop()
        pose, _ = self.pose(el)
        name_el = _child(el, "name")
        static_el = _child(el, "static")
        return replace(
            model,
            name=name_el.text_content().strip() if name_el is not None else model.name,
            pose=compose(pose, model.pose) if _child(el, "pose") is not None else model.pose,
            static=_flag(el, "static", model.static) if static_el is not None else model.static,
            uri=uri,
            source=el.loc,
        )

    def builtin(self, name: str, el: Element) -> WorldModelEntry | Light:
        if name == "sun":
            return Light(  # Gazebo's model://sun
                name="sun",
                type="directional",
                pose=Pose((0.0, 0.0, 10.0)),
                cast_shadows=True,
                specular=(0.2, 0.2, 0.2, 1.0),
                attenuation=Attenuation(1000.0, 0.9, 0.01, 0.001),
                source=el.loc,
            )
        pose, _ = self.pose(el)
        plane = Shape(
            "collision",
            Plane((0.0, 0.0, 1.0), (100.0, 100.0)),
            surface=Surface(mu=100.0, mu2=50.0),
            source=el.loc,
        )
        grey = gazebo_material_colours("Gazebo/Grey")
        assert grey is not None
        visual = Shape(
            "visual",
            Plane((0.0, 0.0, 1.0), (100.0, 100.0)),
            rgba=grey.diffuse,
            material=Material(grey.ambient, grey.diffuse, grey.specular, shininess=grey.shininess),
        )
        link = WorldLink("link", collisions=(plane,), visuals=(visual,), source=el.loc)
        name_el = _child(el, "name")
        return WorldModelEntry(
            name=name_el.text_content().strip() if name_el is not None else "ground_plane",
            pose=pose,
            static=True,
            links=(link,),
            uri="model://ground_plane",
            source=el.loc,
        )

    # --- models -----------------------------------------------------------------------------------
    def model(self, el: Element, parent_pose: Pose, prefix: str = "") -> WorldModelEntry:
        name = el.attrs.get("name")
        if not name:
            msg = "<model> needs a name"
            raise SDFError(msg, el.loc)
        pose, _ = self.pose(el)
        links: list[WorldLink] = []
        joints: list[WorldJoint] = []
        frames: dict[str, Frame] = {}
        for child in el.elements():
            if child.tag == "link":
                link = self.link(child)
                _, rel = self.pose(child)
                frames[link.name] = (link.pose, rel, child.loc)
                links.append(link)
            elif child.tag == "frame":
                fpose, rel = self.pose(child)
                rel = rel or child.attrs.get("attached_to") or None
                frames[child.attrs.get("name", "")] = (fpose, rel, child.loc)
            elif child.tag in ("model", "include"):
                nested = (
                    self.model(child, Pose(), prefix)
                    if child.tag == "model"
                    else self.include(child)
                )
                if isinstance(nested, WorldModelEntry):
                    inner = f"{nested.name}::"
                    links += [
                        replace(lk, name=inner + lk.name, pose=compose(nested.pose, lk.pose))
                        for lk in nested.links
                    ]
                    joints += [
                        replace(
                            j,
                            name=inner + j.name,
                            parent=j.parent if j.parent == "world" else inner + j.parent,
                            child=inner + j.child,
                        )
                        for j in nested.joints
                    ]
        _unique_names("link", name, links)
        resolved = resolve_frames(frames)
        links = [replace(lk, pose=resolved.get(lk.name, lk.pose)) for lk in links]
        link_poses = {lk.name: lk.pose for lk in links}
        for child in el.elements():
            if child.tag == "joint":
                joints.append(self.joint(child, link_poses))
            elif child.tag == "plugin":
                self.warn(
                    child.loc,
                    f"model plugin {child.attrs.get('filename', '?')!r} in {name!r} "
                    "is not supported; ignored",
                )
        _unique_names("joint", name, joints)
        return WorldModelEntry(
            name=name,
            pose=compose(parent_pose, pose),
            static=_flag(el, "static", False),
            links=tuple(links),
            joints=tuple(joints),
            source=el.loc,
        )

    def link(self, el: Element) -> WorldLink:
        name = el.attrs.get("name")
        if not name:
            msg = "<link> needs a name"
            raise SDFError(msg, el.loc)
        pose, _ = self.pose(el)
        collisions = tuple(
            s for c in el.elements() if c.tag == "collision" if (s := self.shape(c)) is not None
        )
        visuals = tuple(
            s for c in el.elements() if c.tag == "visual" if (s := self.shape(c)) is not None
        )
        for c in el.elements():
            if c.tag == "sensor":
                self.warn(c.loc, f"sensor {c.attrs.get('name', '?')!r} of a world model ignored")
        return WorldLink(
            name=name,
            pose=pose,
            inertial=self.inertial(_child(el, "inertial")),
            collisions=collisions,
            visuals=visuals,
            gravity=_flag(el, "gravity", True),
            kinematic=_flag(el, "kinematic", False),
            source=el.loc,
        )

    def inertial(self, el: Element | None) -> Inertial | None:
        if el is None:
            return None
        pose, _ = self.pose(el)
        inertia = _child(el, "inertia")

        def value(tag: str, default: float) -> float:
            return _number(inertia, tag, default) if inertia is not None else default

        mass = _positive(el, "mass", 1.0)
        return Inertial(
            mass=mass,
            ixx=value("ixx", 1.0),
            ixy=value("ixy", 0.0),
            ixz=value("ixz", 0.0),
            iyy=value("iyy", 1.0),
            iyz=value("iyz", 0.0),
            izz=value("izz", 1.0),
            origin=pose,
        )

    def shape(self, el: Element) -> Shape | None:
        geometry_el = _child(el, "geometry")
        if geometry_el is None:
            msg = f"<{el.tag}> needs a <geometry>"
            raise SDFError(msg, el.loc)
        geometry = self.geometry(geometry_el)
        if geometry is None:
            return None
        pose, _ = self.pose(el)
        material = self.material(_child(el, "material")) if el.tag == "visual" else None
        return Shape(
            name=el.attrs.get("name", el.tag),
            geometry=geometry,
            pose=pose,
            surface=self.surface(_child(el, "surface")) if el.tag == "collision" else None,
            rgba=material.diffuse if material is not None else None,
            material=material,
            source=el.loc,
        )

    def geometry(self, el: Element) -> WorldGeometry | None:
        kind = el.first_element()
        if kind is None:
            msg = "<geometry> is empty"
            raise SDFError(msg, el.loc)
        tag = kind.tag
        get: Callable[[str, float], float] = lambda t, d: _number(kind, t, d)  # noqa: E731
        if tag == "box":
            size_el = _child(kind, "size")
            x, y, z = _floats(size_el, 3) if size_el is not None else (1.0, 1.0, 1.0)
            return Box((x, y, z))
        if tag == "cylinder":
            return Cylinder(get("radius", 0.5), get("length", 1.0))
        if tag == "sphere":
            return Sphere(get("radius", 0.5))
        if tag == "plane":
            normal = _child(kind, "normal")
            size = _child(kind, "size")
            n = _floats(normal, 3) if normal is not None else (0.0, 0.0, 1.0)
            s = _floats(size, 2) if size is not None else (100.0, 100.0)
            return Plane((n[0], n[1], n[2]), (s[0], s[1]))
        if tag == "mesh":
            uri_el = _child(kind, "uri")
            if uri_el is None:
                msg = "<mesh> needs a <uri>"
                raise SDFError(msg, kind.loc)
            scale_el = _child(kind, "scale")
            sx, sy, sz = _floats(scale_el, 3) if scale_el is not None else (1.0, 1.0, 1.0)
            return Mesh(str(self.mesh_path(uri_el)), (sx, sy, sz))
        if tag == "polyline":
            points = tuple(
                (p[0], p[1])
                for pt in kind.elements()
                if pt.tag == "point"
                for p in [_floats(pt, 2)]
            )
            if len(points) < 3:
                msg = "<polyline> needs at least 3 <point>s"
                raise SDFError(msg, kind.loc)
            return Polyline(points, get("height", 1.0))
        self.warn(kind.loc, f"<{tag}> geometry is not simulated; shape ignored")
        return None

    def mesh_path(self, uri_el: Element) -> Path:
        uri = uri_el.text_content().strip()
        if uri.startswith("model://"):
            name, _, rest = uri.removeprefix("model://").partition("/")
            directory = self.paths.find(name)
            if directory is None:
                msg = f"mesh {uri!r}: model {name!r} not found (searched: {self.paths.searched()})"
                raise SDFError(msg, uri_el.loc)
            return directory / rest
        if uri.startswith("file://"):
            return Path(uri.removeprefix("file://"))
        path = Path(uri)
        return path if path.is_absolute() else Path(self.path).parent / path

    def surface(self, el: Element | None) -> Surface | None:
        if el is None:
            return None
        friction = _child(el, "friction")
        ode = _child(friction, "ode") if friction is not None else None
        contact = _child(el, "contact")
        contact_ode = _child(contact, "ode") if contact is not None else None

        def opt(parent: Element | None, tag: str) -> float | None:
            c = _child(parent, tag) if parent is not None else None
            return _floats(c, 1)[0] if c is not None else None

        mu, mu2 = opt(ode, "mu"), opt(ode, "mu2")
        return Surface(
            mu=1.0 if mu is None else mu,
            mu2=1.0 if mu2 is None else mu2,
            kp=opt(contact_ode, "kp"),
            kd=opt(contact_ode, "kd"),
            min_depth=opt(contact_ode, "min_depth"),
            max_vel=opt(contact_ode, "max_vel"),
        )

    def material(self, el: Element | None) -> Material | None:
        """A visual's ``<material>``: a Gazebo script name's colours, overridden by the
        colours written out (a missing ambient is the diffuse colour, as sdformat's URDF
        conversion writes both)."""
        if el is None:
            return None
        script = _child(el, "script")
        name_el = _child(script, "name") if script is not None else None
        named = gazebo_material_colours(name_el.text_content()) if name_el is not None else None
        given = {
            tag: self.colour(c, (0.0, 0.0, 0.0, 1.0))
            for tag in ("ambient", "diffuse", "specular", "emissive")
            if (c := _child(el, tag)) is not None
        }
        if named is None and not given:
            return None
        diffuse = given.get("diffuse") or (named.diffuse if named else None)
        ambient = given.get("ambient") or (named.ambient if named else None)
        diffuse = diffuse or ambient or (1.0, 1.0, 1.0, 1.0)
        shininess = _child(el, "shininess")
        return Material(
            ambient=ambient or diffuse,
            diffuse=diffuse,
            specular=given.get("specular") or (named.specular if named else (0.0, 0.0, 0.0, 1.0)),
            emissive=given.get("emissive", (0.0, 0.0, 0.0, 1.0)),
            shininess=_floats(shininess, 1)[0]
            if shininess is not None
            else (named.shininess if named else 0.0),
        )

    def joint(self, el: Element, link_poses: dict[str, Pose]) -> WorldJoint:
        name = el.attrs.get("name", "")
        kind = el.attrs.get("type", "")
        parent_el, child_el = _child(el, "parent"), _child(el, "child")
        if parent_el is None or child_el is None:
            msg = f"joint {name!r} needs <parent> and <child>"
            raise SDFError(msg, el.loc)
        parent, child = parent_el.text_content().strip(), child_el.text_content().strip()
        for role, link in (("parent", parent), ("child", child)):
            if link != "world" and link not in link_poses:
                msg = f"joint {name!r}: {role} link {link!r} is not a link of this model"
                raise SDFError(msg, el.loc, hint=f"links: {', '.join(sorted(link_poses))}")
        pose, _ = self.pose(el)
        axis_el = _child(el, "axis")
        axis = (0.0, 0.0, 1.0)
        lower = upper = None
        damping = friction = 0.0
        if axis_el is not None:
            xyz_el = _child(axis_el, "xyz")
            if xyz_el is not None:
                x, y, z = _floats(xyz_el, 3)
                axis = self._axis_in_child((x, y, z), axis_el, xyz_el, pose, link_poses.get(child))
            limit = _child(axis_el, "limit")
            if limit is not None and kind in ("revolute", "prismatic"):
                lower, upper = _number(limit, "lower", -1e16), _number(limit, "upper", 1e16)
            dynamics = _child(axis_el, "dynamics")
            if dynamics is not None:
                damping = _number(dynamics, "damping", 0.0)
                friction = _number(dynamics, "friction", 0.0)
        return WorldJoint(
            name, kind, parent, child, pose, axis, lower, upper, damping, friction, el.loc
        )

    def _axis_in_child(
        self,
        axis: tuple[float, float, float],
        axis_el: Element,
        xyz_el: Element,
        joint_pose: Pose,
        child_pose: Pose | None,
    ) -> tuple[float, float, float]:
        """SDF < 1.5 gives joint axes in the model frame; 1.5-1.6 in the joint frame unless
        ``use_parent_model_frame``; 1.7+ in ``expressed_in`` (default: the joint frame)."""
        version = tuple(int(p) for p in self.version.split(".")[:2] if p.isdigit())
        in_model = version < (1, 5) or _flag(axis_el, "use_parent_model_frame", False)
        if xyz_el.attrs.get("expressed_in") == "__model__":
            in_model = True
        if in_model and child_pose is not None:
            rotation = matrix(inverse(child_pose))[:3, :3]
            v = rotation @ axis
            return (float(v[0]), float(v[1]), float(v[2]))
        rotation = matrix(joint_pose)[:3, :3]
        v = rotation @ axis
        return (float(v[0]), float(v[1]), float(v[2]))

    # --- whole-world passes -----------------------------------------------------------------------
    def _relative_models(
        self, world_el: Element, models: list[WorldModelEntry]
    ) -> list[WorldModelEntry]:
        """SDF 1.7+: a model pose may be relative_to another model of the world."""
        rel = {
            el.attrs.get("name"): self.pose(el)[1]
            for el in world_el.elements()
            if el.tag == "model"
        }
        by_name = {m.name: m for m in models}
        out = []
        for m in models:
            target = rel.get(m.name)
            if target and target not in ("world", "__world__"):
                base = by_name.get(target)
                if base is None:
                    msg = f"model {m.name!r} pose is relative_to unknown model {target!r}"
                    raise SDFError(msg, m.source)
                m = replace(m, pose=compose(base.pose, m.pose))
            out.append(m)
        return out

    def apply_state(
        self, world_el: Element, models: list[WorldModelEntry]
    ) -> list[WorldModelEntry]:
        """A saved world's ``<state>`` holds where everything was: it wins over the poses."""
        state = _child(world_el, "state")
        if state is None:
            return models
        by_name = {m.name: i for i, m in enumerate(models)}
        out = list(models)
        for el in state.elements():
            if el.tag != "model" or el.attrs.get("name") not in by_name:
                continue
            i = by_name[el.attrs["name"]]
            model = out[i]
            if _child(el, "pose") is not None:
                model = replace(model, pose=self.pose(el)[0])
            scale = _child(el, "scale")
            if scale is not None and any(abs(s - 1.0) > 1e-9 for s in _floats(scale, 3)):
                self.warn(scale.loc, f"model {model.name!r} is scaled in <state>; scale ignored")
            model_from_world = matrix(inverse(model.pose))
            links = list(model.links)
            for link_el in (c for c in el.elements() if c.tag == "link"):
                j = next(
                    (k for k, lk in enumerate(links) if lk.name == link_el.attrs.get("name")), None
                )
                if j is None or _child(link_el, "pose") is None:
                    continue
                world_pose = matrix(self.pose(link_el)[0])
                rel = from_matrix(model_from_world @ world_pose)
                links[j] = replace(links[j], pose=rel)
            out[i] = replace(model, links=tuple(links))
        return out

    def _unique(self, models: list[WorldModelEntry]) -> None:
        seen: dict[str, WorldModelEntry] = {}
        for m in models:
            if m.name in seen:
                msg = f"two models are named {m.name!r} (the first at {seen[m.name].source})"
                raise SDFError(msg, m.source, hint="give the <include> a <name> of its own")
            seen[m.name] = m
