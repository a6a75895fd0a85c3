"""Rigid obstacles with exact signed-distance functions (no mesh file needed).

- ``box``: axis-aligned, ``min`` / ``max`` corners [m];
- ``sphere``: ``center``, ``radius`` [m] (a disc in 2D);
- ``cylinder``: ``center``, ``radius`` and, in 3D, ``axis`` (x, y or z) and
  ``length`` [m] (a finite cylinder centred on ``center``); in 2D a disc.
Signed distances after Quilez's standard exact formulas (positive outside).
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import Field

from geompm.contract.plugin import vector_length_problems
from geompm.obstacles.base import ObstacleParams, RigidObstacle
from geompm.contact.tessellate import box_surface, cylinder_surface, sphere_surface


class BoxParams(ObstacleParams):
    min: list[float] = Field(description="Lower corner [m]")
    max: list[float] = Field(description="Upper corner [m]")


class SphereParams(ObstacleParams):
    center: list[float] = Field(description="Centre [m]")
    radius: float = Field(gt=0, description="Radius [m]")


class CylinderParams(SphereParams):
    axis: Literal["x", "y", "z"] = Field("z", description="Axis direction (3D)")
    length: float | None = Field(None, gt=0, description="Length along the axis [m] (3D)")


class BoxObstacle(RigidObstacle):
    name = "box"
    description = "Rigid axis-aligned box obstacle (exact signed distance)"
    Params = BoxParams

    @classmethod
    def check(cls, params, case):
        out = super().check(params, case) + vector_length_problems(params, case, ("min", "max"))
        if not out and any(a >= b for a, b in zip(params.min, params.max)):
            out.append(("max", "every entry must exceed the same entry of 'min'"))
        return out

    def bounds(self):
        return np.asarray(self.params.min, float), np.asarray(self.params.max, float)

    def surface(self):
        return box_surface(*self.bounds(), self.grid.h)

    def thinnest(self):
        lo, hi = self.bounds()
        return float((hi - lo).min())

    def signed_distance(self, pts):
        lo, hi = self.bounds()
        c, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
        q = np.abs(pts - c) - half
        outside = np.linalg.norm(np.maximum(q, 0.0), axis=1)
        inside = np.minimum(q.max(axis=1), 0.0)
        return outside + inside


class SphereObstacle(RigidObstacle):
    name = "sphere"
    description = "Rigid sphere (disc in 2D) obstacle (exact signed distance)"
    Params = SphereParams

    @classmethod
    def check(cls, params, case):
        return super().check(params, case) + vector_length_problems(params, case, ("center",))

    def bounds(self):
        c = np.asarray(self.params.center, float)
        return c - self.params.radius, c + self.params.radius

    def thinnest(self):
        return 2.0 * self.params.radius

    def surface(self):
        return sphere_surface(self.params.center, self.params.radius, self.grid.h)

    def signed_distance(self, pts):
        return np.linalg.norm(pts - np.asarray(self.params.center, float), axis=1) - self.params.radius


class CylinderObstacle(SphereObstacle):
    name = "cylinder"
    description = "Rigid finite cylinder (disc in 2D) obstacle (exact signed distance)"
    Params = CylinderParams

    @classmethod
    def check(cls, params, case):
        out = super().check(params, case)
        if case.dimension == 3 and params.length is None:
            out.append(("length", "a 3D cylinder needs its 'length' along 'axis'"))
        return out

    def warnings(self) -> list[str]:
        out = super().warnings()
        if self.dim == 2:  # a 2D cylinder is a disc in the x-y plane: axis and length would do nothing
            out += [f"{self.json_path}.{k}: applies to 3D cases only (in 2D the cylinder is a disc in the x-y "
                    "plane); it has no effect: remove it" for k in ("axis", "length")
                    if k in self.params.model_fields_set]
        return out

    def bounds(self):
        lo, hi = super().bounds()
        if self.dim == 3:
            k = "xyz".index(self.params.axis)
            c = self.params.center[k]
            lo[k], hi[k] = c - 0.5 * self.params.length, c + 0.5 * self.params.length
        return lo, hi

    def thinnest(self):
        d = 2.0 * self.params.radius
        return d if self.dim == 2 else min(d, self.params.length)

    def surface(self):
        if self.dim == 2:
            return super().surface()
        p = self.params
        return cylinder_surface(p.center, p.radius, p.axis, p.length, self.grid.h)

    def signed_distance(self, pts):
        if pts.shape[1] == 2:
            return super().signed_distance(pts)
        k = "xyz".index(self.params.axis)
        rel = pts - np.asarray(self.params.center, float)
        radial = np.linalg.norm(np.delete(rel, k, axis=1), axis=1) - self.params.radius
        axial = np.abs(rel[:, k]) - 0.5 * self.params.length
        q = np.stack([radial, axial], axis=1)
        return np.linalg.norm(np.maximum(q, 0.0), axis=1) + np.minimum(q.max(axis=1), 0.0)
