"""Impermeable rigid solids in the free-surface fill (docs/pore-water.md, Free surface).

A particle holds pore pressure where the fill interpolated at it (the particles' volume fraction around
its nodes, kernels.node_fill_one) reaches FREE_SURFACE_FILL.  Against an impermeable solid half of a node's
support lies inside the solid, where no particle can be: without the solid's share the particles that touch
it would read as a free surface and be drained.  Planes (halfspace stages, ``water_boundary``) mirror the
body; every other rigid solid, an obstacle (analytic or STL) or the terrain, adds its own volume fraction
to the node's fill:

    f_solid,I = int N_I(x) chi_solid(x) dx / h^d ~ F(delta_I / h)

with delta_I the node's depth inside the solid along the solid's normal (positive inside) and F the
cumulative distribution of the one-dimensional shape function (the tensor product's integral over a
half-space normal to an axis, exact there; oblique, the same mean and variance).  The depth comes from the
stage's ``solid_depth`` divided by the norm of its gradient (a signed distance has norm 1; the terrain's
vertical depth H(x, y) - z has sqrt(1 + |grad H|^2)), so the normal distance is the same for both.

Nodes within the shape function's reach of the surface are found once at set-up (``SolidFill``); a stage
with a prescribed velocity moves its band by the nearest whole node (an error under h / 2 in its
position).  At a node on or inside an impermeable solid the water's velocity relative to the grains loses
its normal part (no flow across the solid, as at an impermeable wall).  A stage with a ``drained_layer``
(a drained obstacle: a permeable or slit dam) adds no fill, so its face is a drained boundary, and marks
its contact nodes, where the water keeps its velocity relative to the held grains and leaves through it.
"""

from __future__ import annotations

import numpy as np

from geompm.kernels.shape import axis_stencil, support

#: nodes evaluated at once when a solid's band is found (a chunk of the stage's node box)
CHUNK_NODES = 1 << 20
#: a window row: the solids' fill, the drained contact mark, the impermeable surface's normal (3), the depth
#: [m] of a node inside a fixed impermeable solid (0 elsewhere, and for a moving solid: mirror.py)
WIDTH = 6
#: a node this fraction of a spacing outside a solid's surface is on it (a mesh's signed distance carries
#: round-off of its own)
SURFACE_TOLERANCE = 1e-3
#: the band's first cut on the stage's own solid_depth, |depth| < ROUGH_FACTOR (reach + h): a vertical depth
#: exceeds the normal one by sqrt(1 + |grad H|^2), 4 at a 76 degree ground
ROUGH_FACTOR = 4.0
#: samples of the shape function's cumulative distribution per node spacing
CDF_SAMPLES = 400


def kernel_cdf(kind: int):
    """(u, F(u)): the cumulative distribution of the one-dimensional shape function of ``kind`` over
    u = s / h in [-r, r], r = support / 2, by the trapezoid rule on CDF_SAMPLES points per spacing."""
    r = 0.5 * support(kind)
    u = np.linspace(-r, r, int(2 * r * CDF_SAMPLES) + 1)
    w = np.empty_like(u)
    for k, s in enumerate(u):
        base, wt, _ = axis_stencil(float(s), kind, 1.0)  # node 0's weight at a particle at s
        j = -base
        w[k] = wt[j] if 0 <= j < support(kind) else 0.0
    cdf = np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(u))])
    return u, cdf / cdf[-1]


def normal_depth(stage, pts: np.ndarray, step: float):
    """(depth, normal): the stage's solid_depth at pts divided by the norm of its gradient (central
    differences of ``step``), the distance to its surface along the normal, positive inside; and the unit
    normal out of the solid, -grad depth / |grad depth| (m, d)."""
    depth = stage.solid_depth(pts)
    grad = np.zeros_like(pts)
    for a in range(pts.shape[1]):
        up, down = pts.copy(), pts.copy()
        up[:, a] += step
        down[:, a] -= step
        grad[:, a] = (stage.solid_depth(up) - stage.solid_depth(down)) / (2.0 * step)
    norm = np.maximum(np.linalg.norm(grad, axis=1), 1e-12)
    return depth / norm, -grad / norm[:, None]


class SolidFill:
    """Every impermeable solid's node fill and every drained solid's contact nodes (module docstring).

    ``window(lo, nloc, time)`` gives the window's (nn, WIDTH) host array: the solids' fill, 1 at a drained
    solid's contact node, and at a node on or inside an impermeable solid the unit normal out of it (zero
    elsewhere): there the water's velocity relative to the grains loses its normal part, whether the
    solid's contact holds the node or the grains lift off (no water is drawn out of the solid)."""

    def __init__(self, scene):
        g = scene.grid
        self.h, self.dim = g.h, scene.dim
        self.origin = np.asarray(g.origin, float)
        self.ncells = np.asarray(g.ncells, np.int64)
        u, cdf = kernel_cdf(g.kind)
        self.reach = float(u[-1]) * g.h
        self.bands = []  # (stage, node indices (m, d), rows (m, WIDTH))
        for stage in scene.stages:
            if stage.water_boundary() is not None or stage.solid_depth(self.origin[None, :]) is None:
                continue
            band = self._band(stage, u, cdf, stage.drained_layer(), stage.surface_shift(0.0) is None)
            if band is not None:
                self.bands.append((stage,) + band)
        self._key = None
        self._rows = None

    def __bool__(self) -> bool:
        return bool(self.bands)

    def _band(self, stage, u, cdf, drained_layer, fixed):
        """(node indices, rows) of the nodes within the reach of the stage's surface (a node
        deeper than the reach plus a spacing is in no outside particle's stencil); ``fixed``: the solid does
        not move (its nodes' depth is kept for the mirrored velocity)."""
        d, h = self.dim, self.h
        box = stage.node_box(0.0)
        first = np.zeros(d, np.int64)
        last = self.ncells.copy()
        if box is not None:
            first = np.maximum(first, np.asarray(box[0][:d], np.int64))
            last = np.minimum(last, np.asarray(box[1][:d], np.int64))
        if np.any(last < first):
            return None
        axes = [np.arange(first[a], last[a] + 1) for a in range(d)]
        rows = int(np.prod([len(a) for a in axes[1:]])) if d > 1 else 1
        per = max(1, CHUNK_NODES // max(rows, 1))
        keep_idx, keep_rows = [], []
        for start in range(0, len(axes[0]), per):
            grid = np.meshgrid(axes[0][start:start + per], *axes[1:], indexing="ij")
            idx = np.stack([a.ravel() for a in grid], axis=1)
            pts = self.origin + idx * h
            rough = stage.solid_depth(pts)  # a terrain's vertical depth: the normal one times sqrt(1 + |grad H|^2)
            near = np.abs(rough) < (self.reach + h) * ROUGH_FACTOR
            idx, pts = idx[near], pts[near]
            if not len(idx):
                continue
            depth, normal = normal_depth(stage, pts, 0.25 * h)
            row = np.zeros((len(idx), WIDTH))
            if drained_layer is not None:
                keep = depth >= -drained_layer - 1e-9 * h
                row[:, 1] = 1.0
            else:
                keep = (depth > -self.reach) & (depth < self.reach + h)
                row[:, 0] = np.interp(depth / h, u, cdf)
                wall = depth >= -SURFACE_TOLERANCE * h  # on or inside the surface: no flow across it
                row[wall, 2:2 + d] = normal[wall]
                if fixed:
                    row[:, 5] = np.maximum(depth, 0.0)
            keep_idx.append(idx[keep])
            keep_rows.append(row[keep])
        if not keep_idx or not sum(len(k) for k in keep_idx):
            return None
        return np.concatenate(keep_idx), np.concatenate(keep_rows)

    def window(self, lo, nloc, time: float):
        """The (nn, WIDTH) host array of the window at ``time`` (cached while the window and the moving
        solids' node shifts stay)."""
        lo = np.asarray(lo, np.int64)
        nloc = np.asarray(nloc, np.int64)
        shifts = []
        for stage, *_ in self.bands:
            s = stage.surface_shift(time)
            shifts.append(np.zeros(self.dim, np.int64) if s is None
                          else np.rint(np.asarray(s, float)[:self.dim] / self.h).astype(np.int64))
        key = (tuple(lo), tuple(nloc), tuple(tuple(s) for s in shifts))
        if key == self._key:
            return self._rows
        rows = np.zeros((int(np.prod(nloc)), WIDTH))
        for (stage, idx, band), shift in zip(self.bands, shifts):
            local = idx + shift - lo
            inside = np.all((local >= 0) & (local < nloc), axis=1)
            flat = np.ravel_multi_index(tuple(local[inside].T), tuple(nloc))
            np.add.at(rows[:, 0], flat, band[inside, 0])
            np.maximum.at(rows[:, 1], flat, band[inside, 1])
            rows[flat, 2:5] += band[inside, 2:5]
            np.maximum.at(rows[:, 5], flat, band[inside, 5])
        np.minimum(rows[:, 0], 1.0, out=rows[:, 0])
        size = np.linalg.norm(rows[:, 2:5], axis=1)  # two solids' normals at one node: their mean direction
        rows[:, 2:5] /= np.where(size > 0.0, size, 1.0)[:, None]
        self._key, self._rows = key, rows
        return rows
