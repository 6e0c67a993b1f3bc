"""``model://NAME`` resolution, as Gazebo classic does it — and never by downloading.

Search order: ``GAZEBO_MODEL_PATH`` (colon-separated), ``~/.gazebo/models`` (where the course
tells users to put gazebo_models), then the ``models/`` directories ROS packages export with
``<export><gazebo_ros gazebo_model_path="${prefix}/models"/></export>`` (or simply have).
``ground_plane`` and ``sun`` are built in when no directory provides them.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from belvedere.packages import PackageIndex
from belvedere.xmldom import parse_file

__all__ = ["BUILTIN_MODELS", "ModelPaths", "model_sdf_file"]

BUILTIN_MODELS = ("ground_plane", "sun")


@dataclass(frozen=True)
class ModelPaths:
    """Where ``model://`` looks, in order."""

    directories: tuple[Path, ...]

    @classmethod
    def from_environment(
        cls,
        *,
        packages: PackageIndex | None = None,
        environ: Mapping[str, str] | None = None,
        extra: tuple[str | Path, ...] = (),
    ) -> ModelPaths:
        env = os.environ if environ is None else environ
        dirs: list[Path] = [Path(p) for p in extra]
        dirs += [Path(p) for p in env.get("GAZEBO_MODEL_PATH", "").split(":") if p]
        home = env.get("HOME")
        if home:
            dirs.append(Path(home) / ".gazebo" / "models")
        if packages is not None:
            for root in packages.packages().values():
                dirs.extend(_exported_model_dirs(root))
        unique: list[Path] = []
        for d in dirs:
            if d not in unique:
                unique.append(d)
        return cls(tuple(unique))

    def find(self, name: str) -> Path | None:
        """The directory of model ``name`` (holding ``model.config`` or ``model.sdf``)."""
        for base in self.directories:
            candidate = base / name
            if os.path.isfile(candidate / "model.config") or os.path.isfile(
                candidate / "model.sdf"
            ):
                return candidate
        return None

    def searched(self) -> str:
        return ", ".join(str(d) for d in self.directories) or "(no directories)"


def _exported_model_dirs(package_root: Path) -> list[Path]:
    found: list[Path] = []
    manifest = package_root / "package.xml"
    try:
        doc = parse_file(manifest, namespaces=False, keep_blank=False)
    except Exception:  # noqa: BLE001 (a broken manifest only hides its models)
        doc = None
    if doc is not None:
        for export in (e for e in doc.root.elements() if e.tag == "export"):
            for el in export.elements():
                value = el.attrs.get("gazebo_model_path") if el.tag == "gazebo_ros" else None
                if value:
                    found.append(Path(value.replace("${prefix}", str(package_root))))
    if os.path.isdir(package_root / "models"):
        found.append(package_root / "models")
    return found


def model_sdf_file(directory: Path) -> Path:
    """The SDF file of a model directory: the newest ``<sdf version>`` in ``model.config``."""
    config = directory / "model.config"
    if os.path.isfile(config):
        doc = parse_file(config, namespaces=False, keep_blank=False)
        best: tuple[tuple[int, ...], str] | None = None
        for el in doc.root.elements():
            if el.tag != "sdf":
                continue
            version = tuple(int(p) for p in el.attrs.get("version", "0").split(".") if p.isdigit())
            name = el.text_content().strip()
            if name and (best is None or version > best[0]):
                best = (version, name)
        if best is not None:
            return directory / best[1]
    return directory / "model.sdf"
