"""Binary glTF for what viser has no cheap node of its own: plain GL lines, a pixel wide.

viser's lines are quads drawn in two passes (an opaque core and a blended edge), which a
software renderer pays for at every pixel they cover. A glTF primitive in ``LINES`` mode,
unlit (``KHR_materials_unlit``), is what rviz asks of Ogre for its grid: three.js draws it as
``LineSegments`` with its basic line material.
"""

from __future__ import annotations

import json
import struct
from typing import Any

import numpy as np
import numpy.typing as npt

__all__ = ["line_glb"]

FLOAT = 5126
ARRAY_BUFFER = 34962
LINES = 1
UNLIT = "KHR_materials_unlit"


def linear(rgb: tuple[int, int, int]) -> list[float]:
    """An sRGB colour (0-255 a channel) as glTF's linear factors: three.js encodes its output
    back to sRGB, after viser's tone mapping (which viser's own lines go through too)."""
    c = np.asarray(rgb, dtype=np.float64) / 255.0
    lin = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return [float(v) for v in lin]


def _glb(document: dict[str, Any], blob: bytes) -> bytes:
    """A GLB file: the JSON chunk, then the binary one, each padded to 4 bytes."""
    blob += b"\0" * (-len(blob) % 4)
    document["buffers"] = [{"byteLength": len(blob)}]
    text = json.dumps(document, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    size = 12 + 8 + len(text) + 8 + len(blob)
    return b"".join(
        (
            struct.pack("<4sII", b"glTF", 2, size),
            struct.pack("<I4s", len(text), b"JSON"),
            text,
            struct.pack("<I4s", len(blob), b"BIN\0"),
            blob,
        )
    )


def line_glb(segments: npt.NDArray[Any], rgb: tuple[int, int, int]) -> bytes:
    """Opaque GL lines, one pixel wide at any distance (WebGL draws no other width):
    ``segments`` (N, 2, 3) in metres, in one colour. Opaque, so they write depth: a map
    blended just below them does not cover them, and walls in front of them hide them.

    Chromium's software WebGL (SwiftShader) drops a line that crosses the camera's near plane
    rather than clipping it: long lines that pass beside the camera should come in pieces."""
    points = np.ascontiguousarray(np.asarray(segments, dtype=np.float32).reshape(-1, 3))
    blob = points.tobytes()
    document = {
        "asset": {"version": "2.0", "generator": "belvedere"},
        "extensionsUsed": [UNLIT],
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0, "mode": LINES}]}],
        "materials": [
            {
                "pbrMetallicRoughness": {
                    "baseColorFactor": [*linear(rgb), 1.0],
                    "metallicFactor": 0.0,
                },
                "doubleSided": True,
                "extensions": {UNLIT: {}},
            }
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(blob), "target": ARRAY_BUFFER}
        ],
        "accessors": [
            {
                "bufferView": 0,
                "componentType": FLOAT,
                "count": len(points),
                "type": "VEC3",
                "min": [float(v) for v in points.min(axis=0)],  # glTF requires a position's bounds
                "max": [float(v) for v in points.max(axis=0)],
            }
        ],
    }
    return _glb(document, blob)
