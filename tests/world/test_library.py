"""The model library: models on the model path with their model.config names; a broken
model is listed with its error (file and line) and the others still are."""

from __future__ import annotations

from pathlib import Path

import pytest

from belvedere.description.urdf import Box, Cylinder, Sphere
from belvedere.packages import PackageIndex
from belvedere.world import (
    LibraryError,
    ModelPaths,
    SDFError,
    load_model,
    model_library,
    simple_shape,
)
from tests.conftest import EXAMPLES

GOOD_SDF = """<?xml version="1.0"?>
<sdf version="1.6">
  <model name="{name}">
    <static>{static}</static>
    <link name="link">
      <collision name="c"><geometry><box><size>1 2 3</size></box></geometry></collision>
    </link>
  </model>
</sdf>
"""


def _model(base: Path, directory: str, name: str, *, static: bool = False) -> Path:
    d = base / directory
    d.mkdir(parents=True)
    (d / "model.config").write_text(
        f"<?xml version='1.0'?>\n<model>\n  <name>{name}</name>\n"
        "  <sdf version='1.6'>model.sdf</sdf>\n  <description>A test model.</description>\n"
        "</model>\n"
    )
    (d / "model.sdf").write_text(GOOD_SDF.format(name=directory, static=int(static)))
    return d


def test_models_of_every_directory_with_their_config_names(tmp_path: Path) -> None:
    first, second = tmp_path / "first", tmp_path / "second"
    _model(first, "shelf", "Book Shelf", static=True)
    _model(second, "shelf", "Another Shelf")  # shadowed: model://shelf is the first
    _model(second, "cone", "Traffic Cone")
    (second / "materials").mkdir()  # not a model directory: not listed
    (second / "materials" / "textures.png").write_bytes(b"")
    paths = ModelPaths((first, second, tmp_path / "missing"))
    library = model_library(paths)
    assert [(m.name, m.uri, m.ok) for m in library] == [
        ("Book Shelf", "model://shelf", True),
        ("Traffic Cone", "model://cone", True),
        ("Ground Plane", "model://ground_plane", True),
        ("Sun", "model://sun", True),
    ]
    assert [m.light for m in library] == [False, False, False, True]
    assert library[0].directory == first / "shelf"
    assert library[0].description == "A test model."
    shelf = load_model(library[0], paths)
    assert (shelf.name, shelf.uri, shelf.static) == ("shelf", "model://shelf", True)
    assert shelf.links[0].collisions[0].geometry == Box((1.0, 2.0, 3.0))
    assert not load_model(library[1], paths).static
    ground = load_model(library[2], paths)
    assert (ground.name, ground.uri, ground.static) == (
        "ground_plane",
        "model://ground_plane",
        True,
    )
    with pytest.raises(LibraryError, match=r"model://sun is a light, not a model"):
        load_model(library[3], paths)


def test_the_examples_package_exports_its_models() -> None:
    paths = ModelPaths.from_environment(packages=PackageIndex([EXAMPLES]), environ={})
    names = {m.name for m in model_library(paths) if m.ok}
    assert {"belvedere_crate", "belvedere_post", "belvedere_table"} <= names


def test_broken_models_are_listed_with_their_errors(tmp_path: Path) -> None:
    _model(tmp_path, "good", "Good")
    no_config = tmp_path / "no_config"
    no_config.mkdir()
    (no_config / "model.sdf").write_text(GOOD_SDF.format(name="no_config", static=0))
    bad_sdf = _model(tmp_path, "bad_sdf", "Bad SDF")
    (bad_sdf / "model.sdf").write_text(
        "<?xml version='1.0'?>\n<sdf version='1.6'>\n  <model name='bad_sdf'>\n"
        "    <link name='l'><pose>1 2 3</pose></link>\n  </model>\n</sdf>\n"
    )
    bad_xml = _model(tmp_path, "bad_xml", "Bad XML")
    (bad_xml / "model.sdf").write_text("<sdf version='1.6'>\n<model name='x'>\n</sdf>\n")
    bad_config = _model(tmp_path, "bad_config", "Bad config")
    (bad_config / "model.config").write_text("<model>\n  <name>Bad config\n</model>\n")
    missing_sdf = _model(tmp_path, "missing_sdf", "Missing SDF")
    (missing_sdf / "model.sdf").unlink()

    paths = ModelPaths((tmp_path,))
    by_uri = {m.uri: m for m in model_library(paths)}
    assert by_uri["model://good"].ok
    errors = {uri: m.error for uri, m in by_uri.items() if not m.ok}
    assert set(errors) == {
        "model://no_config",
        "model://bad_sdf",
        "model://bad_xml",
        "model://bad_config",
        "model://missing_sdf",
    }
    assert errors["model://no_config"] == (
        f"{no_config}/model.config: error: no model.config (Gazebo lists a model by its "
        "model.config)"
    )
    assert errors["model://bad_sdf"] is not None
    assert errors["model://bad_sdf"].startswith(f"{bad_sdf}/model.sdf:4:")
    assert "<pose> expects 6 numbers" in errors["model://bad_sdf"]
    assert errors["model://bad_xml"] is not None
    assert errors["model://bad_xml"].startswith(f"{bad_xml}/model.sdf:3:")
    assert errors["model://bad_config"] is not None
    assert errors["model://bad_config"].startswith(f"{bad_config}/model.config:3:")
    assert errors["model://missing_sdf"] == (
        f"{missing_sdf}/model.config: error: model://missing_sdf: its model.config names "
        "model.sdf, which does not exist"
    )
    with pytest.raises(SDFError, match=r"bad_sdf/model\.sdf:4:20: error: <pose> expects"):
        load_model(by_uri["model://bad_sdf"], paths)


def test_simple_shapes() -> None:
    box, cylinder, sphere = (simple_shape(k) for k in ("box", "cylinder", "sphere"))
    assert (box.name, box.uri, box.static, box.pose.xyz) == ("unit_box", None, False, (0, 0, 0.5))
    assert box.links[0].collisions[0].geometry == Box((1.0, 1.0, 1.0))
    assert cylinder.links[0].visuals[0].geometry == Cylinder(0.5, 1.0)
    assert sphere.links[0].collisions[0].geometry == Sphere(0.5)
    inertial = cylinder.links[0].inertial
    assert inertial is not None
    assert inertial.mass == 1.0
    assert inertial.izz == pytest.approx(0.125)
    assert inertial.ixx == pytest.approx((3 * 0.25 + 1.0) / 12)
    with pytest.raises(LibraryError, match=r"no simple shape 'cone' \(shapes: box, cylinder"):
        simple_shape("cone")
