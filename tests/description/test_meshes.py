"""Meshes: STL (ascii/binary), OBJ, Collada with units and up-axis; resolution and caching."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import pytest

from belvedere.description.meshes import MeshError, load_mesh, resolve_mesh_path
from belvedere.errors import SourceLocation
from belvedere.packages import PackageIndex

TRIANGLE = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)]


def ascii_stl(path: Path) -> Path:
    lines = ["solid t", "facet normal 0 0 1", "outer loop"]
    lines += [f"vertex {x} {y} {z}" for x, y, z in TRIANGLE]
    lines += ["endloop", "endfacet", "endsolid t"]
    path.write_text("\n".join(lines) + "\n")
    return path


def binary_stl(path: Path) -> Path:
    data = b"\0" * 80 + struct.pack("<I", 1)
    data += struct.pack("<3f", 0, 0, 1)
    for v in TRIANGLE:
        data += struct.pack("<3f", *v)
    data += b"\0\0"
    path.write_bytes(data)
    return path


def obj(path: Path) -> Path:
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    return path


def collada(path: Path, *, unit: float, up: str) -> Path:
    path.write_text(
        f"""<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit meter="{unit}"/><up_axis>{up}</up_axis></asset>
  <library_effects><effect id="fx"><profile_COMMON><technique sid="c"><phong>
    <diffuse><color>1 0 0 1</color></diffuse></phong></technique></profile_COMMON></effect>
  </library_effects>
  <library_materials><material id="red"><instance_effect url="#fx"/></material>
  </library_materials>
  <library_geometries><geometry id="g"><mesh>
    <source id="p"><float_array id="pa" count="9">0 0 0 1000 0 0 0 1000 0</float_array>
      <technique_common><accessor source="#pa" count="3" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <triangles count="1" material="m"><input semantic="VERTEX" source="#v" offset="0"/>
      <p>0 1 2</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#g">
    <bind_material><technique_common><instance_material symbol="m" target="#red"/>
    </technique_common></bind_material></instance_geometry></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
"""
    )
    return path


@pytest.mark.parametrize(
    "make", [ascii_stl, binary_stl, obj], ids=["stl-ascii", "stl-binary", "obj"]
)
def test_formats_and_scale(tmp_path: Path, make: object) -> None:
    suffix = ".obj" if make is obj else ".stl"
    path = make(tmp_path / f"tri{suffix}")  # type: ignore[operator]
    mesh = load_mesh(path, scale=(2.0, 3.0, 1.0))
    assert mesh.faces.shape == (1, 3)
    assert sorted(map(tuple, mesh.vertices.tolist())) == [(0, 0, 0), (0, 3, 0), (2, 0, 0)]


def test_collada_units_up_axis_and_colours(tmp_path: Path) -> None:
    mesh = load_mesh(collada(tmp_path / "mm_yup.dae", unit=0.001, up="Y_UP"))
    # millimetres to metres; Y up turned to Z up (as ROS tools do)
    assert sorted(map(tuple, np.round(mesh.vertices, 9).tolist())) == [
        (0, 0, 0),
        (0, 0, 1),
        (1, 0, 0),
    ]
    assert mesh.face_colors is not None
    assert mesh.face_colors[0].tolist() == pytest.approx([1, 0, 0, 1])
    zup = load_mesh(collada(tmp_path / "m_zup.dae", unit=1.0, up="Z_UP"))
    assert zup.bounds[1].tolist() == pytest.approx([1000, 1000, 0])


def test_cache_by_mtime(tmp_path: Path) -> None:
    path = ascii_stl(tmp_path / "a.stl")
    first = load_mesh(path)
    assert load_mesh(path) is first
    obj(tmp_path / "a.obj")
    path.write_text(path.read_text().replace("vertex 1.0 0.0 0.0", "vertex 5.0 0.0 0.0"))
    import os

    os.utime(path, ns=(1, 10**18))
    assert load_mesh(path).bounds[1][0] == 5.0


def test_missing_and_broken_meshes_name_the_referrer(tmp_path: Path) -> None:
    at = SourceLocation("robot.urdf", 12, 9)
    with pytest.raises(
        MeshError, match=r"robot\.urdf:12:9: error: mesh file .*nope\.stl not found"
    ):
        load_mesh(tmp_path / "nope.stl", requested_at=at)
    bad = tmp_path / "bad.dae"
    bad.write_text("<COLLADA><broken")
    with pytest.raises(
        MeshError, match=r"cannot read mesh .*bad\.dae \(referenced at robot\.urdf:12:9\)"
    ):
        load_mesh(bad, requested_at=at)
    (tmp_path / "x.ply").write_text("ply")
    with pytest.raises(MeshError, match=r"unsupported format '\.ply'"):
        load_mesh(tmp_path / "x.ply")


def test_resolution(tmp_path: Path) -> None:
    pkg = tmp_path / "ws" / "robot_pkg"
    (pkg / "meshes").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package><name>robot_pkg</name></package>")
    urdf = pkg / "urdf" / "r.urdf"
    index = PackageIndex([tmp_path / "ws"])
    got = resolve_mesh_path("package://robot_pkg/meshes/a.stl", relative_to=urdf, packages=index)
    assert got == (pkg / "meshes" / "a.stl").resolve()
    assert (
        resolve_mesh_path("../meshes/a.stl", relative_to=urdf) == pkg / "urdf" / "../meshes/a.stl"
    )
    assert resolve_mesh_path("file:///abs/a.stl") == Path("/abs/a.stl")
    # without a package index, the URDF's own workspace is searched
    assert resolve_mesh_path("package://robot_pkg/meshes/a.stl", relative_to=urdf) == got
