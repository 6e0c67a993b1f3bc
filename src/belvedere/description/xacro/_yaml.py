"""``xacro.load_yaml``: YAML with unit tags (``!degrees 90``), dotted access to the result."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, Final

import yaml

from belvedere.description.xacro._builtins import to_yaml_value
from belvedere.description.xacro._errors import XacroError
from belvedere.description.xacro._interpreter import evaluate
from belvedere.description.xacro._symbols import Scope
from belvedere.yamlfile import Loader, describe_error

__all__ = ["parse_yaml"]

UNITS: Final = {
    "!radians": 1.0,
    "!degrees": math.pi / 180.0,
    "!meters": 1.0,
    "!millimeters": 0.001,
    "!foot": 0.3048,
    "!inches": 0.0254,
}


def _loader(unit_scope: Scope) -> type[Loader]:
    """belvedere's bounded loader, its unit tags evaluating their value as an expression
    (``!degrees 2*45``)."""

    class UnitLoader(Loader):
        pass

    def constructor(factor: float) -> Callable[[yaml.SafeLoader, yaml.Node], float]:
        def construct(loader: yaml.SafeLoader, node: yaml.Node) -> float:
            assert isinstance(node, yaml.ScalarNode)
            return float(evaluate(str(loader.construct_scalar(node)), unit_scope)) * factor

        return construct

    for tag, factor in UNITS.items():
        UnitLoader.add_constructor(tag, constructor(factor))
    return UnitLoader


def parse_yaml(text: str, *, path: str, unit_scope: Scope) -> Any:
    """Parse YAML text; mappings come back with dotted access (``cfg.arm.length``).

    The shared :class:`~belvedere.yamlfile.Loader` bounds nesting and alias expansion."""
    loader = _loader(unit_scope)(text)
    try:
        root = loader.get_single_node()
        data = loader.construct_document(root) if root is not None else None
    except yaml.YAMLError as err:
        msg, where = describe_error(err, path)
        raise XacroError(msg, where) from None
    finally:
        loader.dispose()
    return to_yaml_value(data)
