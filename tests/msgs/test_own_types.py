"""The user's own msg/, srv/ and action/ files: found on the package path (and in the working
directory's catkin workspace), read when first named, and every mistake one error at its
file and line."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from belvedere.bags._model import ros1_definition
from belvedere.errors import BelvedereError
from belvedere.msgs import TypeRegistry, types
from belvedere.msgs._genmsg import InterfaceError
from belvedere.ros1 import message_class
from tests.conftest import EXAMPLES


def _package(root: Path, name: str, files: dict[str, str]) -> Path:
    home = root / name
    home.mkdir(parents=True)
    (home / "package.xml").write_text(f"<package><name>{name}</name></package>")
    for rel, text in files.items():
        (home / rel).parent.mkdir(parents=True, exist_ok=True)
        (home / rel).write_text(text)
    return home


def _registry(root: Path) -> TypeRegistry:
    registry = TypeRegistry()
    registry.add_package_path([root])
    return registry


BAD = [
    ("msg/A.msg", "int32 x\nfoo_msgs/Nope y\n", "msg/A.msg:2:1", "unknown type 'foo_msgs/Nope'"),
    ("msg/A.msg", "int32 x\nNope y\n", "msg/A.msg:2", "unknown type 'pkg/Nope'"),
    ("msg/A.msg", "uint8 BIG=256\n", "msg/A.msg:1", "out of range for uint8 (0 to 255)"),
    ("msg/A.msg", "int32 X=one\n", "msg/A.msg:1", "bad value 'one' for a int32 constant"),
    ("msg/A.msg", "int32 x\n# c\n float64 x\n", "msg/A.msg:3:2", "duplicate name 'x'"),
    ("msg/A.msg", "int32 2x\n", "msg/A.msg:1", "'2x' is not a legal field name"),
    ("msg/A.msg", "int32[2][3] x\n", "msg/A.msg:1", "is not a legal field type"),
    ("msg/A.msg", "int32 x y\n", "msg/A.msg:1", "malformed declaration"),
    ("msg/A.msg", "time T=3\n", "msg/A.msg:1", "'time' cannot be a constant's type"),
    ("msg/A.msg", "A[] children\n", "msg/A.msg:1", "type 'pkg/A' contains itself"),
    ("srv/S.srv", "int32 a\n---\nint32 b\n---\n", "srv/S.srv:4", "this file has 3"),
    ("action/D.action", "int32 a\n---\nint32 b\n", "action/D.action", "this file has 2"),
    ("srv/S.srv", "int32 a\n---\n\nint32 b c\n", "srv/S.srv:4", "malformed declaration"),
    ("action/D.action", "int32 a\n---\n---\nbool 3\n", "action/D.action:4", "legal field name"),
]


@pytest.mark.parametrize(("rel", "text", "where", "message"), BAD)
def test_a_bad_definition_is_one_error_at_its_line(
    tmp_path: Path, rel: str, text: str, where: str, message: str
) -> None:
    home = _package(tmp_path, "pkg", {rel: text})
    registry = _registry(tmp_path)
    with pytest.raises(InterfaceError) as caught:
        registry.resolve("pkg/Anything")
    assert str(caught.value.location).startswith(f"{home}/{where}")
    assert message in caught.value.message
    # asked again, read again: the same error, not "unknown type"
    with pytest.raises(InterfaceError):
        registry.resolve("pkg/Anything")


def test_types_are_read_when_first_named_with_their_dependencies(tmp_path: Path) -> None:
    _package(tmp_path, "base_msgs", {"msg/Cell.msg": "float32 value\n"})
    _package(
        tmp_path,
        "grid_msgs",
        {
            "msg/Grid.msg": (
                "Header header\nbase_msgs/Cell[4] cells\nRow[] rows\nstring LABEL=a # b\n"
            ),
            "msg/Row.msg": "base_msgs/Cell[] cells\n",
        },
    )
    registry = _registry(tmp_path)
    assert "grid_msgs/msg/Grid" not in registry.store.fielddefs
    assert registry.resolve("grid_msgs/Grid") == "grid_msgs/msg/Grid"
    assert "base_msgs/msg/Cell" in registry.store.fielddefs  # read for grid_msgs
    consts, _fields = registry.store.fielddefs["grid_msgs/msg/Grid"]
    assert consts == [("LABEL", "string", "a # b")]
    with pytest.raises(BelvedereError, match="unknown message type 'grid_msgs/Nope'"):
        registry.resolve("grid_msgs/Nope")
    with pytest.raises(BelvedereError, match="unknown message type 'nowhere_msgs/X'"):
        registry.resolve("nowhere_msgs/X")


def test_the_working_directorys_catkin_workspace(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    ws = tmp_path / "catkin_ws"
    _package(ws / "src" / "group", "ws_msgs", {"srv/Ping.srv": "string q\n---\nstring a\n"})
    (ws / ".catkin_workspace").write_text("")
    (ws / "build").mkdir()
    monkeypatch.chdir(ws / "build")
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    registry = TypeRegistry()
    assert registry.resolve_service("ws_msgs/Ping") == "ws_msgs/srv/Ping"
    assert registry.own.interfaces() == {"ws_msgs": {"msg": [], "srv": ["Ping"], "action": []}}


def test_own_types_list_and_their_text(tmp_path: Path) -> None:
    """What a rosmsg/rossrv tool asks: the packages' own types, and each type's text."""
    registry = _registry(EXAMPLES)
    listed = registry.own.interfaces()
    assert listed["learning_topic"]["msg"] == ["Person"]
    assert listed["learning_service"]["srv"] == ["Person"]
    assert listed["learning_action"]["action"] == ["DoDishes"]
    registry.resolve("learning_action/DoDishesActionGoal")
    goal = registry.definitions["learning_action/msg/DoDishesGoal"]
    assert goal.text.splitlines()[1:] == [
        "# Define the goal",
        "uint32 dishwasher_id  # Specify which dishwasher we want to use",
    ]


def test_defaults_constants_and_bags(tmp_path: Path) -> None:
    types().add_package_path([EXAMPLES])
    person: Any = message_class("learning_topic/Person")
    assert (person.unknown, person.male, person.female) == (0, 1, 2)
    msg = person()
    assert (msg.name, msg.age, msg.sex) == ("", 0, 0)
    ros1_type, md5sum, text = ros1_definition("learning_topic/msg/Person")
    assert ros1_type == "learning_topic/Person"
    assert md5sum == person._md5sum
    assert text == (EXAMPLES / "learning_topic" / "msg" / "Person.msg").read_text()
