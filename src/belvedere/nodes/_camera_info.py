"""sensor_msgs/CameraInfo from a calibration file in camera_calibration_parsers' YAML
(``image_width``, ``camera_matrix: {rows, cols, data}``, ...), named by a
``camera_info_url`` (``file://``, ``package://`` or a path); each bad entry one error naming
the file, the line and what was expected."""

from __future__ import annotations

from typing import Any, Final

import numpy as np

from belvedere.errors import ParseError
from belvedere.msgs import types
from belvedere.packages import PackageIndex
from belvedere.yamlfile import YamlDocument, load_yaml_file

__all__ = ["camera_info", "read_calibration"]

# entry: (message field, rows, cols)
_MATRICES: Final = {
    "camera_matrix": ("K", 3, 3),
    "rectification_matrix": ("R", 3, 3),
    "projection_matrix": ("P", 3, 4),
}


def _matrix(doc: YamlDocument, key: str, rows: int, cols: int | None) -> list[float]:
    value = doc.data.get(key)
    where = doc.location(key, "data")
    data = value.get("data") if isinstance(value, dict) else None
    count = None if cols is None else rows * cols
    if (
        not isinstance(data, list)
        or (count is not None and len(data) != count)
        or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in data)
    ):
        wanted = f"{count} numbers" if count is not None else "a list of numbers"
        msg = f"calibration entry {key}: expected {{rows, cols, data}} with data of {wanted}"
        raise ParseError(msg, where)
    return [float(v) for v in data]


def read_calibration(url: str, packages: PackageIndex) -> dict[str, Any]:
    """The calibration a ``camera_info_url`` names, as CameraInfo's fields."""
    path = packages.resolve_uri(url)
    doc = load_yaml_file(path)
    if not isinstance(doc.data, dict):
        msg = "calibration file: expected a mapping of camera_calibration_parsers' entries"
        raise ParseError(msg, doc.location())
    fields: dict[str, Any] = {}
    for key in ("image_width", "image_height"):
        value = doc.data.get(key)
        if isinstance(value, bool) or not isinstance(value, int) or value <= 0:
            msg = f"calibration entry {key}: expected a positive whole number, got {value!r}"
            raise ParseError(msg, doc.location(key))
        fields[key.removeprefix("image_")] = value
    fields["distortion_model"] = str(doc.data.get("distortion_model", "plumb_bob"))
    fields["D"] = _matrix(doc, "distortion_coefficients", 1, None)
    for key, (field, rows, cols) in _MATRICES.items():
        fields[field] = _matrix(doc, key, rows, cols)
    return fields


def camera_info(fields: dict[str, Any] | None, header: Any, size: tuple[int, int]) -> Any:
    """A CameraInfo of ``fields`` (read by :func:`read_calibration`), or an uncalibrated one
    of the picture's ``size`` (width, height) as camera_info_manager gives without a file."""
    info = types().cls("sensor_msgs/CameraInfo")
    roi = types().cls("sensor_msgs/RegionOfInterest")(0, 0, 0, 0, False)
    if fields is None:
        zeros9 = np.zeros(9)
        return info(
            header, size[1], size[0], "", np.zeros(0), zeros9, zeros9, np.zeros(12), 0, 0, roi
        )
    return info(
        header,
        fields["height"],
        fields["width"],
        fields["distortion_model"],
        np.array(fields["D"]),
        np.array(fields["K"]),
        np.array(fields["R"]),
        np.array(fields["P"]),
        0,
        0,
        roi,
    )
