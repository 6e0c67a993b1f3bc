"""Meshes whose textures are missing (as gazebo_models' jersey barrier, construction barrel
and fire hydrant lack their specular maps): one warning per missing file, no traceback."""

from __future__ import annotations

import logging
import os
from pathlib import Path

import pytest

from belvedere.description import meshes
from belvedere.description.meshes import MeshError, load_mesh
from belvedere.errors import SourceLocation
from tests.maps.test_bounded_maps import png_header

# A triangle whose Collada effect takes diffuse, specular and emission from image files
# that are not there (trimesh logs the emission's failure with a traceback).
DAE = """<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit meter="1" name="meter"/><up_axis>Z_UP</up_axis></asset>
  <library_images><image id="spec"><init_from>textures/hydrant_spec.png</init_from></image>
    <image id="diff"><init_from>textures/hydrant_diffuse.png</init_from></image>
    </library_images>
  <library_effects><effect id="fx"><profile_COMMON>
    <newparam sid="s-surface"><surface type="2D"><init_from>spec</init_from></surface>
    </newparam>
    <newparam sid="s-sampler"><sampler2D><source>s-surface</source></sampler2D></newparam>
    <newparam sid="d-surface"><surface type="2D"><init_from>diff</init_from></surface>
    </newparam>
    <newparam sid="d-sampler"><sampler2D><source>d-surface</source></sampler2D></newparam>
    <technique sid="common"><phong><emission><texture texture="s-sampler" texcoord="UVMap"/>
    </emission>
      <diffuse><texture texture="d-sampler" texcoord="UVMap"/></diffuse>
      <specular><texture texture="s-sampler" texcoord="UVMap"/></specular>
    </phong></technique></profile_COMMON></effect></library_effects>
  <library_materials><material id="mat"><instance_effect url="#fx"/></material>
    </library_materials>
  <library_geometries><geometry id="g"><mesh>
    <source id="pos"><float_array id="pa" count="9">0 0 0 1 0 0 0 1 0</float_array>
      <technique_common><accessor source="#pa" count="3" stride="3">
    <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
    </accessor></technique_common></source>
    <source id="uv"><float_array id="ua" count="6">0 0 1 0 0 1</float_array>
      <technique_common><accessor source="#ua" count="3" stride="2">
    <param name="S" type="float"/><param name="T" type="float"/></accessor></technique_common>
    </source>
    <vertices id="v"><input semantic="POSITION" source="#pos"/></vertices>
    <triangles material="m" count="1"><input semantic="VERTEX" source="#v" offset="0"/>
    <input semantic="TEXCOORD" source="#uv" offset="1" set="0"/><p>0 0 1 1 2 2</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#g">
    <bind_material><technique_common><instance_material symbol="m" target="#mat"/>
    </technique_common></bind_material>
  </instance_geometry></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>"""

OBJ = """mtllib box.mtl
v 0 0 0
v 1 0 0
v 0 1 0
vt 0 0
vt 1 0
vt 0 1
usemtl m
f 1/1 2/2 3/3
"""

MTL = """newmtl m
Kd 1 1 1
map_Kd missing_diffuse.png
map_Ks textures/missing_specular.png
"""


def _warnings(caplog: pytest.LogCaptureFixture) -> list[str]:
    assert not [r for r in caplog.records if r.exc_info], "a traceback was logged"
    return [r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING]


def test_missing_collada_textures_are_one_warning_each(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    mesh = tmp_path / "hydrant.dae"
    mesh.write_text(DAE)
    other = tmp_path / "hydrant_copy.dae"
    other.write_text(DAE)
    with caplog.at_level(logging.DEBUG):
        assert len(load_mesh(mesh).faces) == 1
        assert len(load_mesh(other).faces) == 1  # the same missing files: no new warnings
    warnings = _warnings(caplog)
    assert len(warnings) == 2, warnings
    assert any("'textures/hydrant_spec.png'" in w for w in warnings)
    assert any("'textures/hydrant_diffuse.png'" in w for w in warnings)
    assert all(w.startswith(f"{mesh}: warning:") for w in warnings)


def test_missing_obj_textures_are_one_warning_each(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    (tmp_path / "box.obj").write_text(OBJ)
    (tmp_path / "box.mtl").write_text(MTL)
    with caplog.at_level(logging.DEBUG):
        assert len(load_mesh(tmp_path / "box.obj").faces) == 1
    warnings = _warnings(caplog)
    assert len(warnings) == 2, warnings
    assert any("'missing_diffuse.png'" in w for w in warnings)
    assert any("'textures/missing_specular.png'" in w for w in warnings)


def test_a_missing_material_library_is_one_warning(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    (tmp_path / "box.obj").write_text(OBJ)
    with caplog.at_level(logging.DEBUG):
        assert len(load_mesh(tmp_path / "box.obj").faces) == 1
    warnings = _warnings(caplog)
    assert len(warnings) == 1, warnings
    assert "'box.mtl'" in warnings[0]


# --- textures and meshes from the internet -----------------------------------------------------
AT = SourceLocation("robot.urdf", 12, 9)


def test_a_169_megapixel_texture_is_refused_from_its_header(tmp_path: Path) -> None:
    (tmp_path / "box.obj").write_text(OBJ)
    (tmp_path / "box.mtl").write_text("newmtl m\nKd 1 1 1\nmap_Kd huge.png\n")
    (tmp_path / "huge.png").write_bytes(png_header(13000, 13000))
    with pytest.raises(MeshError) as caught:
        load_mesh(tmp_path / "box.obj", requested_at=AT)
    assert caught.value.describe() == (
        f"robot.urdf:12:9: error: mesh file {tmp_path}/box.obj: texture huge.png is 13,000 x "
        "13,000 pixels (169,000,000), more than the 67,108,864 (8192 x 8192) belvedere decodes"
    )


def test_a_collada_texture_past_pillows_own_limit_is_refused(tmp_path: Path) -> None:
    (tmp_path / "textures").mkdir()
    (tmp_path / "textures" / "hydrant_diffuse.png").write_bytes(png_header(20000, 20000))
    (tmp_path / "hydrant.dae").write_text(DAE)
    with pytest.raises(MeshError, match=r"^robot\.urdf:12:9: error: mesh file .*hydrant\.dae: "):
        load_mesh(tmp_path / "hydrant.dae", requested_at=AT)


@pytest.mark.parametrize(("texture", "kind"), [("fifo", "a FIFO"), ("dir", "a directory")])
def test_a_texture_that_is_not_a_regular_file_is_refused_unread(
    tmp_path: Path, texture: str, kind: str
) -> None:
    (tmp_path / "box.obj").write_text(OBJ)
    (tmp_path / "box.mtl").write_text("newmtl m\nKd 1 1 1\nmap_Kd t.png\n")
    if texture == "fifo":
        os.mkfifo(tmp_path / "t.png")
    else:
        (tmp_path / "t.png").mkdir()
    with pytest.raises(
        MeshError, match=rf"robot\.urdf:12:9: .*box\.obj: cannot read texture t\.png: it is {kind}"
    ):
        load_mesh(tmp_path / "box.obj", requested_at=AT)


def test_a_mesh_that_is_a_fifo_is_refused_unread(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "wheel.stl")
    with pytest.raises(
        MeshError,
        match=r"^robot\.urdf:12:9: error: cannot read mesh .*wheel\.stl \(referenced at "
        r"robot\.urdf:12:9\): it is a FIFO \(named pipe\), not a regular file",
    ):
        load_mesh(tmp_path / "wheel.stl", requested_at=AT)


def test_a_mesh_past_the_cap_is_refused_unread(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(meshes, "MESH_FILE_BYTES", 64)
    (tmp_path / "box.obj").write_text(OBJ)
    with pytest.raises(MeshError, match=r"box\.obj: it is 83 bytes, more than the 64 bytes"):
        load_mesh(tmp_path / "box.obj")
