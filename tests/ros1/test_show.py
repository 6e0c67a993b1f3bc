"""``belvedere msg``/``srv`` without an oracle: what the type store gains is listed and shown,
and a wrong name is one error line with the closest names."""

from __future__ import annotations

import pytest
from rosbags.typesys import get_types_from_msg

from belvedere.cli import main
from belvedere.msgs import TypeRegistry, _ros1text
from belvedere.ros1 import _show, _spec

pytestmark = pytest.mark.usefixtures("pristine_types")


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    capsys.readouterr()
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_types_added_to_the_store_are_listed_and_shown(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    # as a workspace's own message package is added: registered in the store
    registry = TypeRegistry()
    added = get_types_from_msg(
        "uint8 LOW=0\nuint8 HIGH=1\nstd_msgs/Header header\nfloat32[] values\nuint8 level",
        "learner_msgs/msg/Reading",
    )
    for suffix, text in (("_Request", "string name"), ("_Response", "learner_msgs/Reading r")):
        (fields,) = get_types_from_msg(text, f"learner_msgs/msg/Get{suffix}").values()
        added[f"learner_msgs/srv/Get{suffix}"] = fields
    registry.store.register(added)
    monkeypatch.setattr(_show, "types", lambda: registry)
    monkeypatch.setattr(_spec, "types", lambda: registry)
    monkeypatch.setattr(_ros1text, "types", lambda: registry)
    assert "learner_msgs/Reading" in run(capsys, "msg", "list")[1].split()
    assert run(capsys, "msg", "package", "learner_msgs")[1] == "learner_msgs/Reading\n"
    assert "learner_msgs" in run(capsys, "msg", "packages")[1].split()
    assert run(capsys, "msg", "show", "learner_msgs/Reading")[1] == (
        "uint8 LOW=0\nuint8 HIGH=1\nstd_msgs/Header header\n  uint32 seq\n  time stamp\n"
        "  string frame_id\nfloat32[] values\nuint8 level\n\n"
    )
    assert run(capsys, "srv", "package", "learner_msgs")[1] == "learner_msgs/Get\n"
    assert run(capsys, "srv", "show", "learner_msgs/Get")[1] == (
        "string name\n---\nlearner_msgs/Reading r\n  uint8 LOW=0\n  uint8 HIGH=1\n"
        "  std_msgs/Header header\n    uint32 seq\n    time stamp\n    string frame_id\n"
        "  float32[] values\n  uint8 level\n\n"
    )
    code, out, _ = run(capsys, "srv", "md5", "learner_msgs/Get")
    assert code == 0
    assert len(out.strip()) == 32


@pytest.mark.parametrize(
    ("argv", "error"),
    [
        (
            ("msg", "show", "geometry_msgs/Header"),
            "error: unknown message type 'geometry_msgs/Header'\n"
            "  hint: did you mean std_msgs/Header?\n",
        ),
        (
            ("msg", "show", "std_msgs/Strng"),
            "error: unknown message type 'std_msgs/Strng'\n  hint: did you mean std_msgs/String?\n",
        ),
        (
            ("msg", "md5", "Headr"),
            "error: unknown message type 'Headr'\n  hint: did you mean Header?\n",
        ),
        (
            ("msg", "package", "geometry_msg"),
            "error: no message types in package 'geometry_msg'\n"
            "  hint: did you mean geometry_msgs?\n",
        ),
        (
            ("srv", "show", "std_srvs/Trigger2"),
            "error: unknown service type 'std_srvs/Trigger2'\n"
            "  hint: did you mean std_srvs/Trigger?\n",
        ),
        (
            ("msg", "show", "std_msgs/"),
            "error: malformed type name 'std_msgs/': expected package/Type, e.g. "
            "geometry_msgs/Twist\n",
        ),
        (
            ("msg", "show", "nothing_like_it"),
            "error: unknown message type 'nothing_like_it'\n"
            "  hint: see 'belvedere msg list' and 'belvedere srv list'\n",
        ),
        (
            ("msg", "show", "a/b/c/d"),
            "error: malformed type name 'a/b/c/d': expected package/Type, e.g. "
            "geometry_msgs/Twist\n",
        ),
    ],
)
def test_wrong_names_are_one_error_with_the_closest(
    capsys: pytest.CaptureFixture[str], argv: tuple[str, ...], error: str
) -> None:
    assert run(capsys, *argv) == (1, "", error)


def test_service_types_and_their_request_fields() -> None:
    assert _show.service_args("std_srvs/SetBool") == ["data"]
    assert _show.service_args("std_srvs/srv/Empty") == []
    assert "std_srvs/SetBool" in _show.type_names("srv")
    assert "builtin_interfaces/Time" not in _show.type_names("msg")  # ROS 1's time: a primitive
