"""A Kinect's point cloud as a message's data, for the viewer's tests."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["kinect_cloud"]


def kinect_cloud(frame: str = "camera") -> dict[str, Any]:
    """A 1 m square of 20 x 20 points standing on the frame's y-z plane, as a Kinect publishes
    a cloud (x, y, z, rgb): the top half red, the bottom half green."""
    rows = []
    for i in range(20):
        for j in range(20):
            rgb = bytes((0, 0, 255, 0)) if i < 10 else bytes((0, 255, 0, 0))  # b, g, r, pad
            xyz = np.array([0.0, (j - 10) * 0.05, (20 - i) * 0.05], dtype="<f4").tobytes()
            rows.append(xyz + rgb)
    field = {"datatype": 7, "count": 1}
    return {
        "header": {"frame_id": frame},
        "height": 1,
        "width": len(rows),
        "fields": [
            {"name": "x", "offset": 0, **field},
            {"name": "y", "offset": 4, **field},
            {"name": "z", "offset": 8, **field},
            {"name": "rgb", "offset": 12, **field},
        ],
        "point_step": 16,
        "row_step": 16 * len(rows),
        "data": list(b"".join(rows)),
        "is_dense": True,
    }
