"""Legacy dialects: ROS Melodic's in-order xacro, Kinetic's two passes, and the `auto` default."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from belvedere.description.xacro import Dialect, XacroError, expand_file, process_file
from belvedere.description.xacro._fix import fix_file
from tests.conftest import DATA, EXAMPLES, Oracle

LEGACY = DATA / "xacro" / "legacy"
FIXTURES = sorted(LEGACY.glob("*.xacro"))
MBOT = EXAMPLES / "mbot_description"
MBOT_WRAPPER = MBOT / "urdf" / "xacro" / "gazebo" / "mbot_gazebo.xacro"
XMLNS = ' xmlns:xacro="http://www.ros.org/wiki/xacro"'


def _ours(fixture: Path, dialect: Dialect, monkeypatch: pytest.MonkeyPatch) -> str:
    monkeypatch.chdir(fixture.parent)
    return process_file(fixture.name, dialect=dialect)


@pytest.mark.oracle
@pytest.mark.parametrize("fixture", FIXTURES, ids=lambda p: p.stem)
@pytest.mark.parametrize(
    ("dialect", "flags"), [(Dialect.MELODIC, []), (Dialect.KINETIC, ["--legacy"])], ids=str
)
def test_identical_to_melodic_xacro(
    fixture: Path,
    dialect: Dialect,
    flags: list[str],
    melodic_oracle: Oracle,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    ref = melodic_oracle.run(fixture.name, *flags, cwd=fixture.parent)
    if ref.returncode != 0:  # then ours fails the same way
        reason = ref.stderr.split("error: ", 1)[1].splitlines()[0]
        with pytest.raises(XacroError, match=re.escape(reason)):
            _ours(fixture, dialect, monkeypatch)
        return
    # 1.13.3 prints one more newline after the document; nothing else differs.
    assert _ours(fixture, dialect, monkeypatch) + "\n" == ref.stdout


@pytest.mark.parametrize("fixture", FIXTURES, ids=lambda p: p.stem)
def test_auto_expands_legacy_like_melodic(fixture: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    if fixture.stem == "ambiguous":  # auto keeps URDF's <inertial>; melodic swallowed it
        assert "<mass " in _ours(fixture, Dialect.AUTO, monkeypatch)
        with pytest.raises(XacroError, match='Unused block "mass"'):
            _ours(fixture, Dialect.MELODIC, monkeypatch)
        return
    if fixture.stem == "macro_leak":  # auto scopes macros as modern xacro does, and says why
        with pytest.raises(XacroError, match="defined inside macro 'definer'"):
            _ours(fixture, Dialect.AUTO, monkeypatch)
        return
    auto = _ours(fixture, Dialect.AUTO, monkeypatch)
    melodic = _ours(fixture, Dialect.MELODIC, monkeypatch).replace(XMLNS, "")
    assert auto == melodic


def test_seed_robot_in_auto_has_all_links_and_one_warning_per_legacy_call() -> None:
    expansion = expand_file(MBOT_WRAPPER)
    root = expansion.document.root
    links = [el for el in root.elements() if el.tag == "link"]
    joints = [el for el in root.elements() if el.tag == "joint"]
    assert [el.attrs["name"] for el in links] == [
        "base_footprint",
        "base_link",
        "left_wheel_link",
        "right_wheel_link",
        "front_caster_link",
        "back_caster_link",
    ]
    assert len(joints) == 5
    messages = [str(w) for w in expansion.warnings]
    first = messages[0]
    assert first.startswith(
        f"{MBOT_WRAPPER}:4:5: warning: deprecated macro call <mbot_base_gazebo>"
    )
    assert "--fix" in first
    named = [w for w in expansion.warnings if w.legacy == "wheel"]
    # once per place the call is written (--fix rewrites each), not once per expansion
    assert [w.location.line for w in named if w.location] == [160, 161]


def test_seed_robot_in_modern_is_empty_and_warns() -> None:
    expansion = expand_file(MBOT_WRAPPER, dialect=Dialect.MODERN)
    root = expansion.document.root
    assert [el.tag for el in root.elements()] == ["material"] * 3 + ["mbot_base_gazebo"]
    assert any("<mbot_base_gazebo> names a macro" in str(w) for w in expansion.warnings)


def test_elements_remember_their_xacro_source() -> None:
    expansion = expand_file(MBOT_WRAPPER)
    wheel = next(
        el for el in expansion.document.root.elements() if el.attrs.get("name") == "left_wheel_link"
    )
    assert wheel.loc is not None
    assert wheel.loc.path.endswith("mbot_base_gazebo.xacro")
    source_line = Path(wheel.loc.path).read_text().splitlines()[wheel.loc.line - 1]
    assert '<link name="${prefix}_wheel_link">' in source_line


def test_ambiguous_macro_name_stays_an_element_in_auto(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(LEGACY)
    expansion = expand_file("ambiguous.xacro")
    assert any("both a macro and a URDF/SDF element" in str(w) for w in expansion.warnings)


def test_two_pass_order_takes_the_last_definition(monkeypatch: pytest.MonkeyPatch) -> None:
    out = _ours(LEGACY / "two_pass.xacro", Dialect.KINETIC, monkeypatch)
    assert '<early p="inside-false-if"/>' in out


def test_kinetic_literal_typing(tmp_path: Path) -> None:
    src = tmp_path / "k.xacro"
    src.write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:property name="t" value="true"/><xacro:property name="h" value="0x10"/>'
        '<a t="${t}" h="${h}"/><xacro:if value="1.0"><yes/></xacro:if></robot>'
    )
    out = process_file(src, dialect=Dialect.KINETIC)
    assert '<a h="16" t="true"/>' in out
    assert "<yes/>" in out
    src.write_text(src.read_text().replace('value="1.0"', 'value="1"'))
    assert '<a h="0x10" t="True"/>' in process_file(src, dialect=Dialect.MODERN)


def test_fix_rewrites_legacy_files_in_place(tmp_path: Path) -> None:
    pkg = tmp_path / "mbot_description"
    shutil.copytree(MBOT, pkg)
    wrapper = pkg / "urdf" / "xacro" / "gazebo" / "mbot_gazebo.xacro"
    base = wrapper.with_name("mbot_base_gazebo.xacro")
    before = process_file(wrapper, dialect=Dialect.MELODIC).replace(XMLNS, "")
    original = base.read_text()

    changes = fix_file(wrapper)

    assert {c.new for c in changes} == {
        "xacro:mbot_base_gazebo",
        "xacro:wheel",
        "xacro:caster",
        "xacro:cylinder_inertial_matrix",
        "xacro:sphere_inertial_matrix",
    }
    assert wrapper.with_name("mbot_gazebo.xacro.orig").is_file()
    assert base.with_name("mbot_base_gazebo.xacro.orig").read_text() == original
    fixed = base.read_text()
    assert '<xacro:wheel prefix="left" reflect="-1"/>' in fixed
    # Nothing but the tags changed.
    undone = fixed
    for change in changes:
        undone = undone.replace(f"<{change.new}", f"<{change.old}")
        undone = undone.replace(f"</{change.new}", f"</{change.old}")
    assert undone == original
    after = expand_file(wrapper, dialect=Dialect.MODERN)
    assert after.warnings == []
    assert after.to_xml() == before


def test_fix_handles_keywords_and_end_tags(tmp_path: Path) -> None:
    shutil.copytree(LEGACY, tmp_path / "legacy")
    target = tmp_path / "legacy" / "unprefixed_keywords.xacro"
    before = process_file(target, dialect=Dialect.MELODIC).replace(XMLNS, "")
    fix_file(target)
    text = target.read_text()
    assert "<xacro:macro name=" in text
    assert "</xacro:macro>" in text
    assert "</xacro:box_link>" in text
    assert "<xacro:include filename" in text
    assert (tmp_path / "legacy" / "inc" / "legacy_part.xacro").read_text().count(
        "<xacro:property"
    ) == 1
    assert process_file(target, dialect=Dialect.MODERN) == before


def test_fix_adds_missing_namespace_declaration(tmp_path: Path) -> None:
    src = tmp_path / "old.xacro"
    src.write_text(
        '<robot name="r">\n  <property name="p" value="1"/>\n  <a v="${p}"/>\n</robot>\n'
    )
    fix_file(src)
    assert src.read_text().startswith(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="r">'
    )
    assert '<a v="1"/>' in process_file(src, dialect=Dialect.MODERN)


def test_python2_float_printing_is_opt_in(tmp_path: Path) -> None:
    src = tmp_path / "f.xacro"
    src.write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<a x="${0.1*3}" p="${pi}" two="${4/2}" mixed="v${0.1*3}" big="${1e16}" i="${7}"/>'
        "</robot>"
    )
    py3 = process_file(src)
    assert 'x="0.30000000000000004"' in py3
    assert 'p="3.141592653589793"' in py3
    py2 = process_file(src, dialect=Dialect.MELODIC, python2_floats=True)
    assert '<a big="1e+16" i="7" mixed="v0.3" p="3.14159265359" two="2.0" x="0.3"/>' in py2


LEGACY_TEXT = '<robot name="r">\n  <property name="p" value="1"/>\n  <a v="${p}"/>\n</robot>\n'


def test_fix_never_overwrites_an_existing_backup(tmp_path: Path) -> None:
    src = tmp_path / "old.xacro"
    src.write_text(LEGACY_TEXT)
    notes = tmp_path / "old.xacro.orig"
    notes.write_text("the user's own notes")
    fix_file(src)
    assert notes.read_text() == "the user's own notes"
    assert (tmp_path / "old.xacro.orig.1").read_text() == LEGACY_TEXT
    assert "<xacro:property" in src.read_text()
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "old.xacro",
        "old.xacro.orig",
        "old.xacro.orig.1",
    ]


def test_fix_through_a_symlink_rewrites_the_real_file(tmp_path: Path) -> None:
    real = tmp_path / "pkg" / "old.xacro"
    real.parent.mkdir()
    real.write_text(LEGACY_TEXT)
    link = tmp_path / "old.xacro"
    link.symlink_to(real)
    fix_file(link)
    assert link.is_symlink()
    assert "<xacro:property" in real.read_text()
    assert real.with_name("old.xacro.orig").read_text() == LEGACY_TEXT
    assert sorted(p.name for p in tmp_path.iterdir()) == ["old.xacro", "pkg"]


def test_fix_on_a_full_disk_changes_nothing(full_disk: Path) -> None:
    from belvedere.fileio import FileWriteError

    padding = "<!--" + "p" * 30_000 + "-->\n"
    src = full_disk / "old.xacro"
    src.write_text(LEGACY_TEXT.replace("</robot>", padding + "</robot>"))
    before = src.read_text()
    with pytest.raises(FileWriteError, match=r"old\.xacro.*: No space left on device"):
        fix_file(src)
    assert src.read_text() == before
    assert sorted(p.name for p in full_disk.iterdir()) == ["old.xacro"]
