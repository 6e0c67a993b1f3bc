"""rviz ``.rviz`` configs: every display, view and global option read as rviz 1.14 reads them,
and written back so that rviz opens them.

A config is YAML. Each display is a mapping with ``Class``, ``Name``, ``Enabled`` and its
properties, named as rviz names them in its Displays panel (``Size (m)``, ``Decay Time``…). A
property with sub-properties is a mapping whose own value is under ``Value`` (``Line Style:
{Value: Lines, Line Width: 0.03}``); ROS 2's rviz writes topics that way too (``Topic: {Value:
/scan, Depth: 5}``). A property the file does not set has rviz's default (:data:`DEFAULTS`,
taken from what rviz 1.14 itself saves for a display it created).

This module is the model only: pure data and YAML, no viser.
"""

from __future__ import annotations

import copy
import math
import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Final

import yaml

from belvedere.bounded import YAML_TEXT_BYTES, LimitError, read_regular_text
from belvedere.errors import ParseError
from belvedere.fileio import FileWriteError, write_file
from belvedere.viewer._rviz_defaults import (
    DEFAULTS,
    GLOBAL_DEFAULTS,
    GROUP,
    TOPIC_KEYS,
    VIEW_DEFAULTS,
)
from belvedere.yamlfile import YamlDocument, load_yaml

__all__ = [
    "DEFAULTS",
    "KNOWN",
    "VIEW_DEFAULTS",
    "RvizConfig",
    "RvizDisplay",
    "RvizView",
    "dump_rviz",
    "format_color",
    "parse_color",
    "read_rviz",
    "to_document",
    "write_rviz",
]

Color = tuple[int, int, int]

KNOWN: dict[str, str] = {
    "rviz/Grid": "Grid",
    "rviz/RobotModel": "RobotModel",
    "rviz/TF": "TF",
    "rviz/LaserScan": "LaserScan",
    "rviz/PointCloud2": "PointCloud2",
    "rviz/Map": "OccupancyGrid",
    "rviz/Odometry": "Odometry",
    "rviz/Path": "Path",
    "rviz/Pose": "PoseStamped",
    "rviz/PoseArray": "PoseArray",
    "rviz/Marker": "Marker",
    "rviz/MarkerArray": "MarkerArray",
    "rviz/Image": "Image",
    "rviz/Camera": "Camera",
}
"""rviz display class → the viewer's display kind, for the classes the viewer draws.

A ``rviz/Map`` whose ``Color Scheme`` is ``costmap`` is a ``Costmap``."""

_COLOR = re.compile(r"\s*(\d{1,3})\s*;\s*(\d{1,3})\s*;\s*(\d{1,3})\s*")


def parse_color(text: str) -> Color:
    """``"255; 0; 0"`` → ``(255, 0, 0)``.

    Raises:
        ValueError: not three integers 0-255 separated by ``;``.
    """
    match = _COLOR.fullmatch(text) if isinstance(text, str) else None
    rgb = tuple(int(c) for c in match.groups()) if match else ()
    if len(rgb) != 3 or max(rgb) > 255:
        msg = f"expected a colour 'R; G; B' (three integers 0-255), got {text!r}"
        raise ValueError(msg)
    return rgb[0], rgb[1], rgb[2]


def format_color(rgb: tuple[int, int, int]) -> str:
    """``(255, 0, 0)`` → ``"255; 0; 0"``, as rviz writes colours."""
    return "; ".join(str(int(c)) for c in rgb)


def _rviz1_class(cls: str) -> str:
    """ROS 2's plugin names (``rviz_default_plugins/LaserScan``, ``rviz_common/Group``) as
    rviz 1 names the same display or view."""
    for prefix in ("rviz_default_plugins/", "rviz_common/"):
        if cls.startswith(prefix):
            return "rviz/" + cls[len(prefix) :]
    return cls


def _is_color(default: Any) -> bool:
    return isinstance(default, str) and _COLOR.fullmatch(default) is not None


class _Properties:
    """Typed access to a display's or view's properties, with rviz's defaults."""

    cls: str
    properties: dict[str, Any]

    def defaults(self) -> Mapping[str, Any]:
        """rviz's default of each property of this class (empty for an unknown class)."""
        return DEFAULTS.get(self.cls, {})

    def _lookup(self, path: str) -> tuple[bool, Any]:
        node: Any = self.properties
        for part in path.split("/"):
            if not isinstance(node, dict) or part not in node:
                return False, None
            node = node[part]
        if isinstance(node, dict):  # a property with sub-properties keeps its own value here
            node = node.get("Value")
        return node is not None, node  # "~" leaves rviz's default, as in rviz

    def get(self, path: str, default: Any = None) -> Any:
        """The value of property ``path`` (``"Line Style/Line Width"``): the file's, else
        rviz's default, else ``default``."""
        found, value = self._lookup(path)
        if found:
            return value
        return self.defaults().get(path, default)

    def set(self, path: str, value: Any) -> None:
        """Set property ``path`` (its ``Value`` when it has sub-properties)."""
        *parents, last = path.split("/")
        node = self.properties
        for part in parents:
            child = node.get(part)
            if not isinstance(child, dict):
                child = {"Value": child} if part in node else {}
                node[part] = child
            node = child
        if isinstance(node.get(last), dict):
            node[last]["Value"] = value
        else:
            node[last] = value

    def number(self, path: str) -> float:
        """A numeric property (validated when the config was read)."""
        return float(self.get(path, 0.0))

    def integer(self, path: str) -> int:
        return int(self.get(path, 0))

    def flag(self, path: str) -> bool:
        return bool(self.get(path, False))

    def text(self, path: str) -> str:
        value = self.get(path, "")
        return "" if value is None else str(value)

    def color(self, path: str = "Color") -> Color:
        return parse_color(str(self.get(path, "255; 255; 255")))


@dataclass
class RvizDisplay(_Properties):
    """One display of a config, as rviz's Displays panel shows it."""

    cls: str
    """The class as rviz 1 names it (``rviz/LaserScan``); ROS 2 names are mapped."""
    name: str
    enabled: bool = True
    properties: dict[str, Any] = field(default_factory=dict)
    """Every other key, as rviz writes it (``Topic``, ``Color: 255; 0; 0``, ``Size (m)``…)."""
    children: list[RvizDisplay] = field(default_factory=list)
    """The displays of a ``rviz/Group``."""
    line: int | None = field(default=None, compare=False)
    """Where the display starts in its file (None for one made in code)."""

    @property
    def kind(self) -> str | None:
        """The viewer's display kind for this class, or None when the viewer has none."""
        if self.cls == "rviz/Map" and self.get("Color Scheme") == "costmap":
            return "Costmap"
        return KNOWN.get(self.cls)

    @property
    def topic_key(self) -> str | None:
        """The property that holds this display's topic, or None for a display without."""
        key = TOPIC_KEYS.get(self.cls, "Topic")
        if key in self.properties or key in self.defaults():
            return key
        return None

    @property
    def topic(self) -> str | None:
        """The topic, resolved as rviz resolves it in the root namespace; None when unset."""
        key = self.topic_key
        value = self.get(key) if key else None
        if not value:
            return None
        name = str(value)
        return name if name.startswith(("/", "~")) else "/" + name

    def walk(self) -> Iterator[RvizDisplay]:
        """This display and, for a group, every display inside it (depth first)."""
        yield self
        for child in self.children:
            yield from child.walk()


@dataclass
class RvizView(_Properties):
    """A camera (view controller): ``rviz/Orbit``, ``rviz/TopDownOrtho``,
    ``rviz/ThirdPersonFollower``, ``rviz/XYOrbit`` or ``rviz/FPS``."""

    cls: str = "rviz/Orbit"
    name: str = "Current View"
    properties: dict[str, Any] = field(default_factory=dict)
    """``Distance``, ``Focal Point: {X, Y, Z}``, ``Pitch``, ``Yaw``, ``Target Frame``…"""

    def defaults(self) -> Mapping[str, Any]:
        return VIEW_DEFAULTS.get(self.cls, {})


_DEFAULT_TOOLS: Final[list[dict[str, Any]]] = [
    {"Class": "rviz/Interact", "Hide Inactive Objects": True},
    {"Class": "rviz/MoveCamera"},
    {"Class": "rviz/Select"},
    {"Class": "rviz/FocusCamera"},
    {"Class": "rviz/Measure"},
    {"Class": "rviz/SetInitialPose", "Topic": "/initialpose"},
    {"Class": "rviz/SetGoal", "Topic": "/move_base_simple/goal"},
    {"Class": "rviz/PublishPoint", "Single click": True, "Topic": "/clicked_point"},
]
_DEFAULT_PANELS: Final[list[dict[str, Any]]] = [
    {"Class": "rviz/Displays", "Name": "Displays"},
    {"Class": "rviz/Selection", "Name": "Selection"},
    {"Class": "rviz/Tool Properties", "Name": "Tool Properties"},
    {"Class": "rviz/Views", "Name": "Views"},
    {"Class": "rviz/Time", "Name": "Time"},
]


@dataclass
class RvizConfig:
    """A whole ``.rviz`` config: global options, displays, views, and the rest untouched."""

    fixed_frame: str = "map"
    background: Color = (48, 48, 48)
    frame_rate: int = 30
    default_light: bool = True
    displays: list[RvizDisplay] = field(default_factory=list)
    view: RvizView = field(default_factory=RvizView)
    """The current view (``Views: Current``)."""
    saved_views: list[RvizView] = field(default_factory=list)
    document: dict[str, Any] = field(default_factory=dict, compare=False, repr=False)
    """The whole YAML as read (panels, tools, window geometry…), so saving keeps what this
    model does not cover."""

    @classmethod
    def default(cls) -> RvizConfig:
        """What rviz starts with when given no config: a Grid, an Orbit view, frame ``map``,
        its usual panels and tools."""
        document = {
            "Panels": copy.deepcopy(_DEFAULT_PANELS),
            "Visualization Manager": {"Class": "", "Tools": copy.deepcopy(_DEFAULT_TOOLS)},
        }
        return cls(displays=[RvizDisplay("rviz/Grid", "Grid", True)], document=document)

    @property
    def hides_left_dock(self) -> bool:
        """Whether rviz opens with its left dock (the Displays panel) hidden."""
        geometry = self.document.get("Window Geometry")
        return isinstance(geometry, dict) and geometry.get("Hide Left Dock") is True

    def walk(self) -> Iterator[RvizDisplay]:
        """Every display, groups' contents included (depth first, in file order)."""
        for display in self.displays:
            yield from display.walk()

    @property
    def unknown(self) -> list[str]:
        """Display classes the viewer does not draw (each once, in file order)."""
        classes: list[str] = []
        for display in self.walk():
            if display.kind is None and display.cls != GROUP and display.cls not in classes:
                classes.append(display.cls)
        return classes


class _GlobalOptions(_Properties):
    """The Global Options of a config, with rviz's defaults."""

    def __init__(self, properties: dict[str, Any]) -> None:
        self.cls = "Global Options"
        self.properties = properties

    def defaults(self) -> Mapping[str, Any]:
        return GLOBAL_DEFAULTS


class _Reader:
    """Builds the model from a parsed document, locating every complaint."""

    def __init__(self, doc: YamlDocument) -> None:
        self.doc = doc

    def fail(self, keys: tuple[str | int, ...], message: str) -> ParseError:
        return ParseError(message, self.doc.location(*keys))

    def mapping(self, value: Any, keys: tuple[str | int, ...], what: str) -> dict[str, Any]:
        if value is None:
            return {}
        if not isinstance(value, dict):
            msg = f"{what} must be a mapping, got {_describe(value)}"
            raise self.fail(keys, msg)
        return value

    def sequence(self, value: Any, keys: tuple[str | int, ...], what: str) -> list[Any]:
        if value is None:
            return []
        if not isinstance(value, list):
            msg = f"{what} must be a list, got {_describe(value)}"
            raise self.fail(keys, msg)
        return value

    def check(
        self, props: dict[str, Any], defaults: Mapping[str, Any], keys: tuple[str | int, ...]
    ) -> None:
        """Each property rviz gives a type has a value of that type."""
        for path, default in defaults.items():
            node: Any = props
            where = keys
            for part in path.split("/"):
                if not isinstance(node, dict) or part not in node:
                    node = None
                    break
                node, where = node[part], (*where, part)
            if isinstance(node, dict):
                node, where = node.get("Value"), (*where, "Value")
            if node is None:
                continue
            self.check_value(node, default, where, path)

    def check_value(self, value: Any, default: Any, keys: tuple[str | int, ...], name: str) -> None:
        if isinstance(default, bool):
            if not isinstance(value, bool):
                msg = f"{name!r} must be true or false, got {_describe(value)}"
                raise self.fail(keys, msg)
        elif isinstance(default, int | float):
            if isinstance(value, bool) or not isinstance(value, int | float):
                msg = f"{name!r} must be a number, got {_describe(value)}"
                raise self.fail(keys, msg)
            if not _in_range(value, default):
                shown = repr(value) if len(repr(value)) < 40 else f"{repr(value)[:20]}…"
                msg = f"{name!r} is out of range, got {shown}"
                raise self.fail(keys, msg)
        elif _is_color(default):
            try:
                parse_color(value)
            except ValueError as err:
                msg = f"{name!r}: {err}"
                raise self.fail(keys, msg) from None

    def display(self, item: Any, keys: tuple[str | int, ...]) -> RvizDisplay:
        data = dict(self.mapping(item, keys, "a display"))
        if "Class" not in data:
            msg = "a display without 'Class' (expected e.g. 'Class: rviz/LaserScan')"
            raise self.fail(keys, msg)
        written = data.pop("Class")
        if not isinstance(written, str) or not written:
            msg = f"'Class' must be a display class such as rviz/LaserScan, got {written!r}"
            raise self.fail((*keys, "Class"), msg)
        cls = _rviz1_class(written)
        name = data.pop("Name", None)
        name = "" if name is None else str(name)  # rviz leaves an unnamed display unnamed
        # rviz enables a display only when told to ("Enabled", or its own "Value").
        enabled = data.pop("Enabled", data.get("Value", False))
        data.pop("Value", None)
        if not isinstance(enabled, bool):
            msg = f"'Enabled' must be true or false, got {_describe(enabled)}"
            raise self.fail((*keys, "Enabled"), msg)
        children: list[RvizDisplay] = []
        if cls == GROUP:
            listed = self.sequence(data.pop("Displays", None), (*keys, "Displays"), "Displays")
            children = [self.display(d, (*keys, "Displays", i)) for i, d in enumerate(listed)]
        if written != cls and cls in TOPIC_KEYS and "Topic" in data:
            # ROS 2 keeps every topic under "Topic"; rviz 1 reads these under another key.
            data[TOPIC_KEYS[cls]] = data.pop("Topic")
        self.check(data, DEFAULTS.get(cls, {}), keys)
        line = self.doc.location(*keys).line or None
        return RvizDisplay(cls, name, enabled, data, children, line)

    def view(self, item: Any, keys: tuple[str | int, ...], default_name: str) -> RvizView:
        data = dict(self.mapping(item, keys, "a view"))
        written = data.pop("Class", "rviz/Orbit")
        if not isinstance(written, str) or not written:
            msg = f"'Class' must be a view class such as rviz/Orbit, got {written!r}"
            raise self.fail((*keys, "Class"), msg)
        cls = _rviz1_class(written)
        name = data.pop("Name", None)
        view = RvizView(cls, default_name if name is None else str(name), data)
        self.check(data, view.defaults(), keys)
        return view

    def config(self) -> RvizConfig:
        root = self.mapping(self.doc.data, (), "an rviz config")
        vm_keys: tuple[str, ...] = ("Visualization Manager",)
        manager = self.mapping(root.get("Visualization Manager"), vm_keys, "Visualization Manager")
        options_keys = (*vm_keys, "Global Options")
        options = self.mapping(manager.get("Global Options"), options_keys, "Global Options")
        self.check(options, GLOBAL_DEFAULTS, options_keys)
        listed = self.sequence(manager.get("Displays"), (*vm_keys, "Displays"), "Displays")
        displays = [self.display(d, (*vm_keys, "Displays", i)) for i, d in enumerate(listed)]
        views_keys = (*vm_keys, "Views")
        views = self.mapping(manager.get("Views"), views_keys, "Views")
        current = views.get("Current")
        view = (
            self.view(current, (*views_keys, "Current"), "Current View")
            if current is not None
            else RvizView()
        )
        saved_keys = (*views_keys, "Saved")
        saved = self.sequence(views.get("Saved"), saved_keys, "Saved views")
        saved_views = [self.view(v, (*saved_keys, i), f"View {i + 1}") for i, v in enumerate(saved)]
        given = _GlobalOptions(options)
        return RvizConfig(
            fixed_frame=given.text("Fixed Frame"),
            background=given.color("Background Color"),
            frame_rate=given.integer("Frame Rate"),
            default_light=given.flag("Default Light"),
            displays=displays,
            view=view,
            saved_views=saved_views,
            document=root,
        )


def _in_range(value: float, default: float) -> bool:
    """rviz keeps a property in a 32-bit int or a float32 (whose range is kept generous)."""
    try:
        number = float(value)
    except OverflowError:
        return False
    if not math.isfinite(number):
        return False
    if isinstance(default, int):
        return -(2**31) <= number < 2**31
    return abs(number) < 1e38


def _describe(value: Any) -> str:
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, list):
        return "a list"
    return repr(value)


def read_rviz(path: str | Path) -> RvizConfig:
    """Read a ``.rviz`` file (rviz 1 or ROS 2's rviz2).

    Raises:
        ParseError: the file cannot be read, is not YAML, or a value is not what rviz
            expects there (``nav.rviz:12:7: error: 'Alpha' must be a number, got 'abc'``).
    """
    shown = str(path)
    try:
        text = read_regular_text(path, limit=YAML_TEXT_BYTES, what="rviz config")
    except LimitError as err:
        raise ParseError(err.message, err.location) from None
    return _Reader(load_yaml(text, path=shown)).config()


def _display_document(display: RvizDisplay) -> dict[str, Any]:
    out: dict[str, Any] = copy.deepcopy(display.properties)
    out.update(Class=display.cls, Name=display.name, Enabled=display.enabled)
    if display.cls == GROUP:
        out["Displays"] = [_display_document(d) for d in display.children]
    else:
        out["Value"] = display.enabled  # rviz writes a display's checkbox twice
    return out


def _view_document(view: RvizView) -> dict[str, Any]:
    out: dict[str, Any] = copy.deepcopy(view.properties)
    out.update(Class=view.cls, Name=view.name)
    return out


def to_document(config: RvizConfig) -> dict[str, Any]:
    """The YAML document of ``config``: its ``document`` with the modelled parts replaced."""
    doc = copy.deepcopy(config.document)
    manager = doc.get("Visualization Manager")
    if not isinstance(manager, dict):
        manager = doc["Visualization Manager"] = {"Class": ""}
    options = manager.get("Global Options")
    if not isinstance(options, dict):
        options = manager["Global Options"] = {}
    options.update(
        {
            "Fixed Frame": config.fixed_frame,
            "Background Color": format_color(config.background),
            "Frame Rate": int(config.frame_rate),
            "Default Light": bool(config.default_light),
        }
    )
    manager["Displays"] = [_display_document(d) for d in config.displays]
    views = manager.get("Views")
    if not isinstance(views, dict):
        views = manager["Views"] = {}
    views["Current"] = _view_document(config.view)
    views["Saved"] = [_view_document(v) for v in config.saved_views] or None
    return doc


class _Dumper(yaml.SafeDumper):
    """YAML as rviz writes it: block style, keys sorted, lists indented, ``~`` for nothing."""

    def increase_indent(self, flow: bool = False, indentless: bool = False) -> None:
        super().increase_indent(flow, False)


_Dumper.add_representer(
    type(None), lambda dumper, _: dumper.represent_scalar("tag:yaml.org,2002:null", "~")
)


def dump_rviz(config: RvizConfig) -> str:
    """The text of ``config`` as a ``.rviz`` file."""
    return yaml.dump(
        to_document(config),
        Dumper=_Dumper,
        default_flow_style=False,
        sort_keys=True,
        allow_unicode=True,
        width=1 << 16,
    )


def write_rviz(config: RvizConfig, path: str | Path) -> None:
    """Write ``config`` to ``path`` whole or not at all (the old file stays on any error).

    Raises:
        FileWriteError: the file cannot be written (names it and the reason).
    """
    unfit = _unwritable(config)
    if unfit:
        raise FileWriteError(path, unfit, existed=Path(path).exists())
    write_file(path, dump_rviz(config))


def _plain(value: Any) -> bool:
    if isinstance(value, dict):
        return all(isinstance(k, str) and _plain(v) for k, v in value.items())
    if isinstance(value, list):
        return all(_plain(v) for v in value)
    return value is None or isinstance(value, str | int | float | bool)


def _unwritable(config: RvizConfig) -> str | None:
    """What in ``config`` YAML cannot hold (a value set in code), or None."""
    owners: list[tuple[str, str, dict[str, Any]]] = [
        ("display", d.name, d.properties) for d in config.walk()
    ]
    owners += [("view", v.name, v.properties) for v in [config.view, *config.saved_views]]
    for what, name, properties in owners:
        for key, value in properties.items():
            if not _plain(value):
                kind = type(value).__name__
                return f"{what} {name!r}: property {key!r} holds a {kind}, not a YAML value"
    if not _plain(config.document):
        return "the document holds values that are not YAML"
    return None
