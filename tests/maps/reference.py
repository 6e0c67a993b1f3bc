"""map_server's image loader and map_saver's writer, restated pixel by pixel in plain Python.

A slow, literal reading of map_server 1.x's ``loadMapFromFile`` (the loop over pixels in
SDL's byte order, one branch per mode) and of map_saver's ``mapCallback``, to check the
vectorised code against. Written from the C++ sources' behaviour, not their text.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt


def _to_byte(value: float) -> int:
    """C's double → unsigned char for values in range: truncation."""
    return math.trunc(value) & 0xFF


def _as_int8(byte: int) -> int:
    """unsigned char → int8 (the message's data is int8): wraps above 127."""
    return byte - 256 if byte > 127 else byte


def loader_cells(
    pixels: npt.NDArray[np.uint8],
    has_alpha: bool,
    *,
    negate: bool,
    occ_th: float,
    free_th: float,
    mode: str,
) -> list[int]:
    """``map.data`` as map_server fills it: index ``x + (height - y - 1) * width``."""
    height, width, n_channels = pixels.shape
    avg_channels = n_channels if mode == "trinary" or not has_alpha else n_channels - 1
    data = [0] * (width * height)
    for j in range(height):
        for i in range(width):
            p = [int(v) for v in pixels[j, i]]
            color_sum = sum(p[:avg_channels])
            color_avg = color_sum / float(avg_channels)
            alpha = 1 if n_channels == 1 else p[n_channels - 1]
            if negate:
                color_avg = 255 - color_avg
            index = i + (height - j - 1) * width
            if mode == "raw":
                data[index] = _as_int8(_to_byte(color_avg))
                continue
            occ = (255 - color_avg) / 255.0
            if occ > occ_th:
                value = 100
            elif occ < free_th:
                value = 0
            elif mode == "trinary" or alpha < 1.0:
                value = -1
            else:
                ratio = (occ - free_th) / (occ_th - free_th)
                value = _as_int8(_to_byte(1 + 98 * ratio))
            data[index] = value
    return data


def saver_pixels(data: list[int], width: int, height: int, occupied: int, free: int) -> bytes:
    """The PGM raster map_saver writes for ``map.data``."""
    out = bytearray()
    for y in range(height):
        for x in range(width):
            value = data[x + (height - y - 1) * width]
            if 0 <= value <= free:
                out.append(254)
            elif value >= occupied:
                out.append(0)
            else:
                out.append(205)
    return bytes(out)
