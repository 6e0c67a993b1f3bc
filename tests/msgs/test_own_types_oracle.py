"""Differential tests of the user's own message, service and action types against Debian's
genmsg, genpy and genaction (``genmsg_oracle.py``, run by ``/usr/bin/python3``): MD5 sums,
``_full_text``, ``__slots__``, constants, and the wire bytes of default and filled messages,
for the course's packages and for generated definitions."""

from __future__ import annotations

import json
import keyword
import subprocess
from itertools import count
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from belvedere.msgs import types
from belvedere.ros1 import message_class, serialize_message, service_class
from tests.conftest import DATA, EXAMPLES
from tests.debian_ros import ROS_PYTHON, missing_debian_ros
from tests.ros1.filling import filled

pytestmark = pytest.mark.oracle

ORACLE = Path(__file__).with_name("genmsg_oracle.py")
GENACTION = Path("/usr/lib/actionlib_msgs/genaction.py")
INTERFACES = DATA / "msgs" / "interfaces"
PACKAGES = {
    "learning_topic": EXAMPLES / "learning_topic",
    "learning_service": EXAMPLES / "learning_service",
    "learning_action": EXAMPLES / "learning_action",
    "beginner_tutorials": INTERFACES / "beginner_tutorials",
    "team_msgs": INTERFACES / "team_msgs",
}
_ACTION = [f"learning_action/msg/DoDishes{part}" for part in ("Goal", "Result", "Feedback")]
MESSAGES = [
    "learning_topic/msg/Person",
    "beginner_tutorials/msg/Num",
    "beginner_tutorials/srv/AddTwoIntsRequest",
    "beginner_tutorials/srv/AddTwoIntsResponse",
    "learning_service/srv/PersonRequest",
    "learning_service/srv/PersonResponse",
    *_ACTION,
    *[f"learning_action/msg/DoDishesAction{p}" for p in ("", "Goal", "Result", "Feedback")],
    "team_msgs/msg/Team",
    "team_msgs/msg/Badge",
    "team_msgs/msg/Empty",
]
SERVICES = ["beginner_tutorials/AddTwoInts", "learning_service/Person"]
USER = frozenset(PACKAGES)
_SEPARATOR = "\n" + "=" * 80 + "\n"


def _ros1(name: str) -> str:
    pkg, _, base = name.split("/")
    return f"{pkg}/{base}"


def _ask(packages: dict[str, Path], messages: list[str], services: list[str]) -> Any:
    why = missing_debian_ros("genpy, std_msgs.msg, actionlib_msgs.msg", GENACTION)
    if why:
        pytest.skip(why)
    request = {
        "packages": {name: str(path) for name, path in packages.items()},
        "messages": {n: serialize_message(filled(_store(n), 3)).hex() for n in messages},
        "services": services,
    }
    run = subprocess.run(
        [str(ROS_PYTHON), str(ORACLE)],
        input=json.dumps(request),
        capture_output=True,
        text=True,
        check=False,
    )
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout)


def _store(name: str) -> str:
    cls: Any = message_class(_ros1(name))
    return str(cls._spec.store_name)


def _sections(full_text: str) -> list[tuple[str, str]]:
    """(type, text) of each part of a ``_full_text``, the type's own first (named '')."""
    parts = full_text.split(_SEPARATOR)
    out = [("", parts[0])]
    for part in parts[1:]:
        head, _, text = part.partition("\n")
        out.append((head.removeprefix("MSG: "), text))
    return out


def _declarations(text: str) -> list[str]:
    """A stock type's declarations, whatever their order and spelling: the type store keeps
    no comments, puts constants first and names every type with its package."""
    out = []
    for line in text.split("\n"):
        clean = line.split("#", 1)[0].strip()
        if clean:
            typ, _, rest = clean.partition(" ")
            out.append(typ.rsplit("/", 1)[-1] + " " + rest.replace(" ", ""))
    return sorted(out)


def _assert_full_text(ours: str, theirs: str, user: frozenset[str]) -> None:
    mine, real = _sections(ours), _sections(theirs)
    assert [n for n, _ in mine] == [n for n, _ in real]
    for (name, text), (_, real_text) in zip(mine, real, strict=True):
        if not name or name.split("/")[0] in user:
            assert text == real_text, name  # the user's files: exactly as written
        else:
            assert _declarations(text) == _declarations(real_text), name


def _assert_same(name: str, answer: dict[str, Any], user: frozenset[str]) -> None:
    cls: Any = message_class(_ros1(name))
    assert cls._md5sum == answer["md5sum"], name
    _assert_full_text(cls._full_text, answer["full_text"], user)
    assert list(cls.__slots__) == answer["slots"]
    assert list(cls._slot_types) == answer["slot_types"]
    constants = {c: getattr(cls, c) for c, _t, _v in cls._spec.constants}
    assert constants == answer["constants"]
    assert serialize_message(cls()).hex() == answer["default_bytes"]
    msg = filled(cls._spec.store_name, 3)
    assert serialize_message(msg).hex() == answer["bytes"]
    assert str(msg) == answer["str"]


@pytest.fixture(scope="module")
def answers() -> Any:
    types().add_package_path(PACKAGES.values())
    return _ask(PACKAGES, MESSAGES, SERVICES)


@pytest.mark.parametrize("name", MESSAGES)
def test_course_types_match_genpy(answers: Any, name: str) -> None:
    _assert_same(name, answers[name], USER)


@pytest.mark.parametrize("name", SERVICES)
def test_course_services_match_genpy(answers: Any, name: str) -> None:
    cls: Any = service_class(name)
    assert cls._md5sum == answers[name]["md5sum"]
    assert cls._type == answers[name]["type"]


def test_known_sums(answers: Any) -> None:
    """The sums ROS users meet in the tutorials, written down (not only compared)."""
    assert message_class("beginner_tutorials/Num")._md5sum == "57d3c40ec3ac3754af76a83e6e73127a"
    assert service_class("beginner_tutorials/AddTwoInts")._md5sum == (
        "6a2e34150c00229791cc89ff309fff21"
    )


# --- generated definitions ------------------------------------------------------------------

_INTS = {
    "int8": (-128, 127),
    "uint8": (0, 255),
    "int16": (-(2**15), 2**15 - 1),
    "uint32": (0, 2**32 - 1),
    "int64": (-(2**63), 2**63 - 1),
}
_FIELD_TYPES = [
    *_INTS,
    "float32",
    "float64",
    "string",
    "bool",
    "char",
    "byte",
    "time",
    "duration",
    "Header",
    "geometry_msgs/Point",
    "learning_topic/Person",
]
_names = st.from_regex(r"[a-z][a-z0-9_]{0,6}", fullmatch=True).filter(
    lambda n: not keyword.iskeyword(n) and n != "self"
)
_space = st.sampled_from(["", " ", "  "])


@st.composite
def _field(draw: st.DrawFn, name: str) -> str:
    typ = draw(st.sampled_from(_FIELD_TYPES))
    if typ != "Header":
        typ += draw(st.sampled_from(["", "", "[]", "[1]", "[3]"]))
    comment = draw(st.sampled_from(["", "  # a comment", "\t#x"]))
    return f"{typ}{draw(st.sampled_from([' ', '   ']))}{name}{comment}"


@st.composite
def _constant(draw: st.DrawFn, name: str) -> str:
    typ = draw(st.sampled_from([*_INTS, "float64", "bool", "string"]))
    if typ in _INTS:
        value = str(draw(st.integers(*_INTS[typ])))
    elif typ == "float64":
        value = repr(draw(st.floats(allow_nan=False, allow_infinity=False, width=32)))
    elif typ == "bool":
        value = draw(st.sampled_from(["True", "False", "1", "0"]))
    else:
        value = draw(st.from_regex(r"[a-z #=]{0,8}", fullmatch=True))
    return f"{typ} {name}{draw(_space)}={draw(_space)}{value}"


@st.composite
def _definition(draw: st.DrawFn) -> str:
    names = draw(st.lists(_names, min_size=0, max_size=6, unique=True))
    lines = []
    for i, name in enumerate(names):
        if draw(st.booleans()) and i % 2:
            lines.append(draw(_constant(name.upper())))
        else:
            lines.append(draw(_field(name)))
        if draw(st.integers(0, 4)) == 0:
            lines.append(draw(st.sampled_from(["", "# between", "   "])))
    return "\n".join(lines) + draw(st.sampled_from(["", "\n"]))


_serial = count()


@settings(max_examples=3)
@given(st.lists(_definition(), min_size=6, max_size=6))
def test_generated_definitions_match_genpy(tmp_path_factory: Any, texts: list[str]) -> None:
    root = tmp_path_factory.mktemp("defs")
    package = f"generated{next(_serial)}_msgs"
    home = root / package
    (home / "msg").mkdir(parents=True)
    (home / "package.xml").write_text(f"<package><name>{package}</name></package>")
    for i, text in enumerate(texts):
        (home / "msg" / f"T{i}.msg").write_text(text)
    types().add_package_path([root, *PACKAGES.values()])
    names = [f"{package}/msg/T{i}" for i in range(len(texts))]
    answer = _ask({package: home, "learning_topic": PACKAGES["learning_topic"]}, names, [])
    for name in names:
        _assert_same(name, answer[name], frozenset({package, "learning_topic"}))
