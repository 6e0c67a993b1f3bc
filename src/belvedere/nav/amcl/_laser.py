"""amcl's laser models, over every particle and beam at once.

Each model turns a scan into one factor per particle that multiplies its weight:

- ``likelihood_field``: ``1 + sum(pz**3)`` over the beams, ``pz = z_hit·exp(-d²/2s²) +
  z_rand/range_max`` where ``d`` is the distance from the beam's end to the nearest occupied
  cell (at most ``laser_likelihood_max_dist``; off the map counts as that). Beams at or past
  the range's end are left out. Since ``pz`` depends only on the end's cell, it is kept per cell
  (cubed, float32) and a scan costs one lookup per particle and beam.
- ``likelihood_field_prob``: ``exp(sum(log pz))`` with the same ``pz``; with ``do_beamskip``
  (once the filter has converged) a beam is only used when more than ``beam_skip_threshold``
  of the particles put its end within ``beam_skip_distance`` of an obstacle — unless so many
  beams are skipped (``beam_skip_error_threshold``) that the filter is probably wrong.
- ``beam``: ``1 + sum(pz**3)`` with the ray cast from the particle to its first non-free cell:
  a gaussian about it (``z_hit``), an exponential short of it (``z_short``, ``lambda_short``),
  ``z_max`` at the range's end and ``z_rand`` uniform. Rays are marched together over the
  distance to the nearest stopping cell, so long free stretches take a few steps.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Final

import numpy as np
import numpy.typing as npt

from belvedere.nav.amcl._map import AmclMap

__all__ = ["LASER_MODELS", "LaserData", "LaserModel", "LaserParams", "laser_data"]

LASER_MODELS: Final = ("likelihood_field", "beam", "likelihood_field_prob")

_CHUNK = 1024
"""Particles whose beams are placed together (their float32 arrays stay in the cache)."""

_COMPACT_EVERY = 4
"""Steps the beam model's rays take between compactions of those still marching."""

_WIDE_TABLE = 1 << 21
"""Cells a table with the wide border may hold (8 MB of float32), or four times the map's if
that is more: beyond, the border is one cell and the beam ends are clipped (the wide border
saves ~5% of the likelihood field's time, not worth a table many times the map's size)."""

Floats = npt.NDArray[np.float64]
Float32s = npt.NDArray[np.float32]


@dataclass(frozen=True)
class LaserParams:
    """The laser model's parameters, with amcl's defaults."""

    model: str = "likelihood_field"
    max_beams: int = 30
    z_hit: float = 0.95
    z_short: float = 0.1
    z_max: float = 0.05
    z_rand: float = 0.05
    sigma_hit: float = 0.2
    lambda_short: float = 0.1
    likelihood_max_dist: float = 2.0
    do_beamskip: bool = False
    beam_skip_distance: float = 0.5
    beam_skip_threshold: float = 0.3
    beam_skip_error_threshold: float = 0.9


@dataclass(frozen=True)
class LaserData:
    """One scan as amcl's models take it: ``ranges`` (m, readings at or under the minimum
    already moved to ``range_max``) and ``bearings`` (rad, in the base frame)."""

    ranges: Floats
    bearings: Floats
    range_max: float


def laser_data(
    ranges: npt.ArrayLike,
    angle_min: float,
    angle_increment: float,
    range_min: float,
    range_max: float,
    *,
    laser_min_range: float = -1.0,
    laser_max_range: float = -1.0,
) -> LaserData:
    """A scan's readings as amcl hands them to its model: the range limits from the scan,
    narrowed by ``laser_min_range``/``laser_max_range`` when those are positive, and every
    reading at or under the minimum counted as a maximum-range reading."""
    values = np.asarray(ranges, dtype=np.float64)
    top = min(range_max, laser_max_range) if laser_max_range > 0 else range_max
    bottom = max(range_min, laser_min_range)
    out = np.where(values <= bottom, top, values)
    bearings = angle_min + np.arange(len(values), dtype=np.float64) * angle_increment
    return LaserData(out, bearings, float(top))


class LaserModel:
    """Weighs particles against scans on one map (the model's tables are built once)."""

    def __init__(self, params: LaserParams, amcl_map: AmclMap) -> None:
        if params.model not in LASER_MODELS:
            msg = f"unknown laser model {params.model!r} (one of {', '.join(LASER_MODELS)})"
            raise ValueError(msg)
        self.params = params
        self.map = amcl_map
        self._tables: dict[tuple[float, int], Float32s] = {}
        self._steps: Float32s | None = None
        self.skipped_beams = 0
        """Beams beam skipping left out of the last update."""

    # --- which beams -------------------------------------------------------------------------
    def beams(self, data: LaserData) -> tuple[Floats, Floats]:
        """The ranges and bearings the model uses: every ``step``-th beam (amcl's integer
        ``(count - 1) / (max_beams - 1)``), without NaNs and, for the likelihood fields,
        without readings at or past the range's end."""
        count = len(data.ranges)
        step = max((count - 1) // max(self.params.max_beams - 1, 1), 1)
        ranges = data.ranges[::step]
        bearings = data.bearings[::step]
        keep = ~np.isnan(ranges)
        if self.params.model != "beam":
            keep &= ranges < data.range_max
        return ranges[keep], bearings[keep]

    # --- the likelihood field ----------------------------------------------------------------
    def _pad(self, range_max: float) -> int:
        """Cells of off-map border around the map in the tables: enough that a particle moved
        in to ``range_max + 1`` cells inside the border's outer edge still has every beam end
        off the map (see ``_end_cells``), or a single cell where that table would be large (see
        ``_WIDE_TABLE``), and the beam ends are clipped instead."""
        reach = math.ceil(range_max / self.map.resolution)
        pad = 2 * reach + 2
        cells = (self.map.height + 2 * pad) * (self.map.width + 2 * pad)
        if cells > max(_WIDE_TABLE, 4 * self.map.height * self.map.width):
            return 1
        return pad

    def _bordered(self, inner: npt.ArrayLike, off_map: float, range_max: float) -> Float32s:
        """``inner`` (one value per map cell) in the middle of a ``_pad`` border of
        ``off_map``, flattened."""
        pad = self._pad(range_max)
        out = np.full(
            (self.map.height + 2 * pad, self.map.width + 2 * pad), off_map, dtype=np.float32
        )
        out[pad:-pad, pad:-pad] = inner
        return out.ravel()

    def _pz_table(self, range_max: float, power: int) -> Float32s:
        """pz**power (power 0: log pz) per cell, over the map within its ``_pad`` border of the
        off-map value, flattened."""
        key = (range_max, power)
        cached = self._tables.get(key)
        if cached is not None:
            return cached
        p = self.params
        denom = 2.0 * p.sigma_hit * p.sigma_hit
        rand = p.z_rand / range_max

        def pz_of(dist: Floats) -> Floats:
            pz = p.z_hit * np.exp(-(dist * dist) / denom) + rand
            out: Floats = np.log(pz) if power == 0 else pz**power
            return out

        dist = self.map.occ_dist(p.likelihood_max_dist).astype(np.float64)
        # the same float64 arithmetic as the map's cells, then float32
        off_map = pz_of(np.array([p.likelihood_max_dist]))[0]
        table = self._bordered(
            pz_of(dist).astype(np.float32), float(np.float32(off_map)), range_max
        )
        if len(self._tables) > 8:
            self._tables.clear()  # a laser whose range keeps changing
        self._tables[key] = table
        return table

    def _end_cells(
        self,
        poses: Floats,
        headings: tuple[Floats, Floats],
        laser_pose: tuple[float, float, float],
        ranges: Floats,
        bearings: Floats,
        range_max: float,
    ) -> Iterator[tuple[slice, npt.NDArray[np.int32]]]:
        """Flat indices into the bordered tables of each beam's end cell, for ``_CHUNK``
        particles at a time (rows of the particles in ``slice``); the array is reused for the
        next chunk. Chunks keep the float32 work in the cache.

        Positions are in the cells of the map with a one-cell border (the map's first cell
        is 1), in float32 as they have always been computed, so that every end lands in the
        cell it always did; the wide border's offset is added to the truncated cells. With
        it, only the particles' positions are clipped, not every end: a particle clipped was
        farther than ``range_max`` from the map, so all its beams end off the map, and still
        do from where it was moved to. A negative end truncates towards zero, one cell nearer
        the map, but never onto it. (A complex64 multiply would take fewer passes, but numpy
        fuses its multiply-add, which moves a few ends in a million to the next cell.)"""
        m = self.map
        inv = 1.0 / m.resolution
        pad = self._pad(range_max)
        lx, ly, lth = laser_pose
        c = headings[0].astype(np.float32)
        s = headings[1].astype(np.float32)
        # the laser's position in the one-cell-bordered map's cell units
        px = ((poses[:, 0] + c * lx - s * ly - m.origin_x) * inv + 1.0).astype(np.float32)
        py = ((poses[:, 1] + s * lx + c * ly - m.origin_y) * inv + 1.0).astype(np.float32)
        clip_ends = pad == 1
        if not clip_ends:
            # a cell to spare on both sides of the map and of the table
            reach = pad // 2 - 1  # ceil(range_max / resolution)
            np.clip(px, -reach, m.width + reach + 2, out=px)
            np.clip(py, -reach, m.height + reach + 2, out=py)
        rc = (ranges * np.cos(bearings + lth) * inv).astype(np.float32)[None, :]
        rs = (ranges * np.sin(bearings + lth) * inv).astype(np.float32)[None, :]
        n, b = len(poses), len(ranges)
        size = min(n, _CHUNK)
        fx_buf = np.empty((size, b), dtype=np.float32)
        fy_buf = np.empty((size, b), dtype=np.float32)
        tmp_buf = np.empty((size, b), dtype=np.float32)
        ix_buf = np.empty((size, b), dtype=np.int32)
        iy_buf = np.empty((size, b), dtype=np.int32)
        stride = m.width + 2 * pad
        shift = (pad - 1) * (stride + 1)  # the one-cell border's cell (0, 0) in the table
        for lo in range(0, n, size):
            hi = min(lo + size, n)
            k = hi - lo
            fx, fy, tmp, ix, iy = fx_buf[:k], fy_buf[:k], tmp_buf[:k], ix_buf[:k], iy_buf[:k]
            ck, sk = c[lo:hi, None], s[lo:hi, None]
            np.multiply(ck, rc, out=fx)
            np.multiply(sk, rs, out=tmp)
            fx -= tmp
            fx += px[lo:hi, None]
            np.multiply(sk, rc, out=fy)
            np.multiply(ck, rs, out=tmp)
            fy += tmp
            fy += py[lo:hi, None]
            if clip_ends:
                # beyond the map: the border cell (truncation is floor once clipped to >= 0)
                np.clip(fx, 0.0, m.width + 1, out=fx)
                np.clip(fy, 0.0, m.height + 1, out=fy)
            ix[...] = fx
            iy[...] = fy
            iy *= stride
            iy += ix
            if shift:
                iy += shift
            yield slice(lo, hi), iy

    def weigh(
        self,
        poses: Floats,
        laser_pose: tuple[float, float, float],
        data: LaserData,
        *,
        converged: bool = False,
        headings: tuple[Floats, Floats] | None = None,
    ) -> Floats:
        """The factor each particle's weight is multiplied by for this scan (``headings``:
        the cosines and sines of the particles' yaws, if the caller has them)."""
        ranges, bearings = self.beams(data)
        model = self.params.model
        if model == "beam":
            return self._beam(poses, laser_pose, ranges, bearings, data.range_max)
        if len(ranges) == 0:
            return np.ones(len(poses))
        if headings is None:
            headings = np.cos(poses[:, 2]), np.sin(poses[:, 2])
        chunks = self._end_cells(poses, headings, laser_pose, ranges, bearings, data.range_max)
        if model == "likelihood_field":
            table = self._pz_table(data.range_max, 3)
            sums = np.empty(len(poses), dtype=np.float32)
            for rows, cells in chunks:
                table.take(cells).sum(axis=1, out=sums[rows])
            factors: Floats = 1.0 + sums.astype(np.float64)
            return factors
        cells = np.concatenate([part.copy() for _, part in chunks])
        return self._prob(poses, cells, data.range_max, converged)

    def _prob(
        self, poses: Floats, cells: npt.NDArray[np.int32], range_max: float, converged: bool
    ) -> Floats:
        p = self.params
        logs = self._pz_table(range_max, 0).take(cells)
        self.skipped_beams = 0
        if p.do_beamskip and converged:
            dist = self._bordered(self.map.occ_dist(p.likelihood_max_dist), np.inf, range_max)
            near = (dist.take(cells) < p.beam_skip_distance).sum(axis=0)
            use = near / len(poses) > p.beam_skip_threshold
            skipped = int((~use).sum())
            if skipped < cells.shape[1] * p.beam_skip_error_threshold:
                logs = logs[:, use]
                self.skipped_beams = skipped
        factors: Floats = np.exp(logs.sum(axis=1, dtype=np.float64))
        return factors

    # --- the beam model ----------------------------------------------------------------------
    def expected_ranges(
        self,
        poses: Floats,
        laser_pose: tuple[float, float, float],
        bearings: Floats,
        range_max: float,
    ) -> Floats:
        """(N, B) metres from each particle's laser to the first cell that is not free (or
        the map's edge) along each bearing, ``range_max`` if none is that near."""
        m = self.map
        inv = 1.0 / m.resolution
        lx, ly, lth = laser_pose
        c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
        px = (poses[:, 0] + c * lx - s * ly - m.origin_x) * inv + 1.0
        py = (poses[:, 1] + s * lx + c * ly - m.origin_y) * inv + 1.0
        heading = poses[:, 2][:, None] + (bearings + lth)[None, :]
        dx, dy = np.cos(heading).ravel(), np.sin(heading).ravel()
        steps = self._march_steps()
        height, width = steps.shape
        # only the origins are clipped: one off the map starts (and stops) in the border's
        # stop cells; a ray from inside never leaves the border, as no step crosses a stop
        # cell (a step of d - sqrt(2) ends at least sqrt(2)/2 from every stop cell's centre,
        # a half-cell step from a cell next to one ends in it)
        px = np.clip(px, 0, width - 1)
        py = np.clip(py, 0, height - 1)
        ox = np.repeat(px, len(bearings))
        oy = np.repeat(py, len(bearings))
        limit = range_max * inv
        flat = steps.ravel()
        t = np.zeros(len(dx))
        # the first step is the same for every ray of a particle: they start in one cell
        first = flat.take(py.astype(np.intp) * width + px.astype(np.intp))
        at = np.repeat(first if limit > 0.0 else np.zeros_like(first), len(bearings))
        at = at.astype(np.float64)
        # the rays not yet known to have stopped; a ray stops where it hits or once past the
        # range, and then steps by 0, so the set is only compacted every few steps (gathering
        # from the full arrays on every step would cost more than the step)
        rays = np.arange(len(dx))
        while len(rays):
            for _ in range(_COMPACT_EVERY):
                x = dx * at
                x += ox
                y = dy * at
                y += oy
                cell = y.astype(np.intp)
                cell *= width
                cell += x.astype(np.intp)
                step = flat.take(cell)
                going = step > 0.0
                going &= at < limit
                step *= going
                at += step
            stopped = ~going
            t[rays[stopped]] = at[stopped]
            rays, at = rays[going], at[going]
            ox, oy, dx, dy = ox[going], oy[going], dx[going], dy[going]
        out = np.minimum(t * m.resolution, range_max)
        return out.reshape(len(poses), len(bearings))

    def _march_steps(self) -> Float32s:
        """Per cell of the map with its one-cell border, how far (cells) a ray in it may
        step: 0 in a cell that stops rays; else a free cell d cells from the nearest stop
        lets the ray skip d - sqrt(2) cells (both ends may sit anywhere in their cells), and
        never less than half a cell. Kept per cell, as the steps are float32 either way."""
        if self._steps is None:
            field = self.map.free_dist()
            self._steps = np.where(field > 0.0, np.maximum(field - math.sqrt(2.0), 0.5), 0.0)
        return self._steps

    def _beam(
        self,
        poses: Floats,
        laser_pose: tuple[float, float, float],
        ranges: Floats,
        bearings: Floats,
        range_max: float,
    ) -> Floats:
        p = self.params
        if len(ranges) == 0:
            return np.ones(len(poses))
        expected = self.expected_ranges(poses, laser_pose, bearings, range_max)
        # the terms that depend on the reading alone, once per beam (at most one of z_max's
        # and z_rand's is not 0, so adding them first rounds as adding them in turn)
        short = p.z_short * p.lambda_short * np.exp(-p.lambda_short * ranges)
        flat = np.where(ranges == range_max, p.z_max, 0.0)
        flat += np.where(ranges < range_max, p.z_rand / range_max, 0.0)
        z = np.subtract(ranges[None, :], expected, out=expected)
        pz = z * z
        pz /= -(2.0 * p.sigma_hit * p.sigma_hit)
        np.exp(pz, out=pz)
        pz *= p.z_hit
        pz += np.where(z < 0, short[None, :], 0.0)
        pz += flat[None, :]
        factors: Floats = 1.0 + (pz**3).sum(axis=1)
        return factors
