"""``.cfg`` files read in the sandbox, the description's rules, and the generated module."""

from __future__ import annotations

import math
from pathlib import Path
from types import ModuleType

import pytest

from belvedere.errors import BelvedereError
from belvedere.ros1.dynamic_reconfigure import _cfgfile
from belvedere.ros1.dynamic_reconfigure._cfgfile import CfgError, load_cfg
from belvedere.ros1.dynamic_reconfigure._cfgmodule import fill_config_module
from belvedere.ros1.dynamic_reconfigure._description import ReconfigureError
from tests.conftest import EXAMPLES

TUTORIALS = EXAMPLES / "dynamic_tutorials" / "cfg" / "Tutorials.cfg"

HEAD = (
    "#!/usr/bin/env python\n"
    'PACKAGE = "demo"\n'
    "from dynamic_reconfigure.parameter_generator_catkin import *\n"
    "gen = ParameterGenerator()\n"
)
TAIL = 'exit(gen.generate(PACKAGE, "demo", "Demo"))\n'


def _cfg(tmp_path: Path, body: str) -> Path:
    path = tmp_path / "Demo.cfg"
    path.write_text(HEAD + body + TAIL)
    return path


def test_the_tutorial_cfg_gives_what_ros_generates() -> None:
    description = load_cfg(TUTORIALS)
    module = ModuleType("TutorialsConfig")
    fill_config_module(module, description)
    assert module.defaults == {
        "int_param": 50,
        "double_param": 0.5,
        "str_param": "Hello World",
        "bool_param": True,
        "size": 1,
    }
    assert module.min["int_param"] == 0
    assert module.max["double_param"] == 1.0
    assert module.min["str_param"] == ""
    assert module.max["bool_param"] is True
    assert module.type["size"] == "int"
    assert module.all_level == 0
    assert module.Tutorials_Small == 0
    assert module.Tutorials_ExtraLarge == 3
    assert [p["name"] for p in module.config_description["parameters"]] == [
        "int_param",
        "double_param",
        "str_param",
        "bool_param",
        "size",
    ]


def test_groups_bounds_and_defaults(tmp_path: Path) -> None:
    body = (
        'tab = gen.add_group("motion", type="tab")\n'
        'tab.add("speed", double_t, 4, "m/s", 0.5, 0, 2)\n'
        'gen.add("count", int_t, 1, "how many")\n'
    )
    description = load_cfg(_cfg(tmp_path, body))
    (motion,) = description.root.groups
    assert (motion.name, motion.type, motion.id, motion.parent) == ("motion", "tab", 1, 0)
    count = description.param("count")
    assert (count.default, count.min, count.max) == (0, -(2**31), 2**31 - 1)
    speed = description.param("speed")
    assert speed.accept(5) == 2.0
    assert speed.accept(-1) == 0.0
    assert description.level({"speed": 1.0, "count": 3}, {"speed": 0.5, "count": 3}) == 4
    assert description.level({"speed": 1.0, "count": 4}, {"speed": 0.5, "count": 3}) == 5


def test_values_a_server_refuses() -> None:
    description = load_cfg(TUTORIALS)
    size = description.param("size")
    assert size.accept(9) == 3  # clamped to its max first, as ROS clamps
    with pytest.raises(ReconfigureError, match="is a double"):
        description.param("double_param").accept("high")
    with pytest.raises(ReconfigureError, match="NaN"):
        description.param("double_param").accept(math.nan)
    with pytest.raises(ReconfigureError, match="no parameter 'speed'"):
        description.merged(description.defaults, {"speed": 1})


def test_an_enum_refuses_a_value_in_range_that_is_none_of_its_constants(tmp_path: Path) -> None:
    body = (
        'odd = gen.enum([gen.const("One", int_t, 1, "one"), gen.const("Three", int_t, 3, "three")],'
        ' "odd")\n'
        'gen.add("k", int_t, 0, "d", 1, 0, 5, edit_method=odd)\n'
    )
    k = load_cfg(_cfg(tmp_path, body)).param("k")
    assert k.accept(3) == 3
    with pytest.raises(ReconfigureError, match="none of its enum's values"):
        k.accept(2)


@pytest.mark.parametrize(
    ("body", "line", "message"),
    [
        ("import os\n", 5, "may not import os"),
        ('open("/etc/passwd").read()\n', 5, "name 'open' is not defined"),
        ("x = ().__class__\n", 5, "leading underscore"),
        ('gen.add("n", int_t, 0, "d", "ten")\n', 5, "'n' is a int, but its default is 'ten'"),
        ('gen.add("s", str_t, 0, "d", "a", 0, 1)\n', 5, "takes no min or max"),
        ('gen.add("n", int_t, 0, "d")\ngen.add("n", int_t, 0, "d")\n', 0, "added twice"),
        ('gen.add("bad name", int_t, 0, "d")\n', 5, "not a ROS name"),
        ("gen.add(\n", 5, "invalid Python"),
        ('e = gen.enum([gen.const("A", int_t, "one", "d")], "d")\n', 5, "constant 'A' is a int"),
    ],
)
def test_a_bad_cfg_is_one_error_at_its_line(
    tmp_path: Path, body: str, line: int, message: str
) -> None:
    path = _cfg(tmp_path, body)
    with pytest.raises(CfgError, match=message) as caught:
        load_cfg(path)
    location = caught.value.location
    assert location is not None
    assert location.path == str(path)
    if line:
        assert location.line == line


def test_a_cfg_that_never_ends_is_stopped(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(_cfgfile, "_SECONDS", 1.0)
    with pytest.raises(CfgError, match="ran too long"):
        load_cfg(_cfg(tmp_path, "while True:\n    pass\n"))


def test_a_missing_cfg(tmp_path: Path) -> None:
    with pytest.raises(BelvedereError, match="cannot read"):
        load_cfg(tmp_path / "Nope.cfg")
