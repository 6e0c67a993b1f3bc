"""ROS package discovery."""

from __future__ import annotations

from pathlib import Path

import pytest

from belvedere.errors import SourceLocation
from belvedere.packages import PackageIndex, PackageNotFoundError, find_package_root


def make_package(path: Path, name: str | None = None) -> Path:
    path.mkdir(parents=True, exist_ok=True)
    tag = f"<name>{name}</name>" if name else ""
    (path / "package.xml").write_text(f'<?xml version="1.0"?><package format="2">{tag}</package>')
    return path


def test_name_in_manifest_wins_over_folder(tmp_path: Path) -> None:
    make_package(tmp_path / "src" / "folder_name", "real_name")
    index = PackageIndex([tmp_path / "src"])
    assert index.find("real_name") == (tmp_path / "src" / "folder_name").resolve()
    with pytest.raises(PackageNotFoundError):
        index.find("folder_name")


def test_crawl_skips_hidden_and_does_not_descend_into_packages(tmp_path: Path) -> None:
    make_package(tmp_path / ".hidden" / "secret")
    outer = make_package(tmp_path / "outer")
    make_package(outer / "nested_inside")
    make_package(tmp_path / "ignored" / "pkg")
    (tmp_path / "ignored" / "CATKIN_IGNORE").touch()
    make_package(tmp_path / "a" / "b" / "deep")
    assert set(PackageIndex([tmp_path]).packages()) == {"outer", "deep"}


def test_search_order_first_wins(tmp_path: Path) -> None:
    first = make_package(tmp_path / "one" / "pkg")
    make_package(tmp_path / "two" / "pkg")
    index = PackageIndex.from_environment(
        package_path=[tmp_path / "one"],
        environ={"ROS_PACKAGE_PATH": str(tmp_path / "two")},
    )
    assert index.find("pkg") == first.resolve()


def test_environment_variables_in_order(tmp_path: Path) -> None:
    make_package(tmp_path / "b" / "pkg")
    a = make_package(tmp_path / "a" / "pkg")
    env = {"BELVEDERE_PACKAGE_PATH": str(tmp_path / "a"), "ROS_PACKAGE_PATH": str(tmp_path / "b")}
    assert PackageIndex.from_environment(environ=env).find("pkg") == a.resolve()


def test_workspace_of_the_input_file(tmp_path: Path) -> None:
    src = tmp_path / "catkin_ws" / "src"
    robot = make_package(src / "robot_description")
    make_package(src / "group" / "robot_gazebo")
    xacro = robot / "urdf" / "robot.xacro"
    xacro.parent.mkdir()
    xacro.touch()
    assert find_package_root(xacro) == robot
    index = PackageIndex.from_environment(near=xacro, environ={})
    assert index.find("robot_gazebo") == (src / "group" / "robot_gazebo").resolve()


def test_missing_package_names_requester_and_search_path(tmp_path: Path) -> None:
    index = PackageIndex([tmp_path])
    where = SourceLocation("robot.xacro", 3, 5)
    with pytest.raises(PackageNotFoundError) as info:
        index.find("nope", requested_at=where)
    text = str(info.value)
    assert text.startswith("robot.xacro:3:5: error: package 'nope' not found; searched:")
    assert str(tmp_path.resolve()) in text


def test_uris(tmp_path: Path) -> None:
    pkg = make_package(tmp_path / "meshes_pkg")
    index = PackageIndex([tmp_path])
    assert index.resolve_uri("package://meshes_pkg/meshes/a.stl") == pkg.resolve() / "meshes/a.stl"
    assert index.resolve_uri("file:///abs/b.dae") == Path("/abs/b.dae")
    assert index.resolve_uri("rel/c.obj") == Path("rel/c.obj")
    with pytest.raises(PackageNotFoundError):
        index.resolve_uri("package://other/x.stl")
