"""Rigid obstacle from a surface mesh (STL, OBJ, PLY: anything trimesh reads), 3D.

The mesh is scaled, rotated (``rotate``: degrees about x, then y, then z) and
translated, in that order, into the case's frame [m].  It must be watertight
(a closed surface): the signed distance and the inside/outside test need it.
Open surfaces (``thin``) are not supported: close the mesh in your CAD tool
(or give the wall a thickness).  Signed distance from libigl (files/mesh.py).
"""

from __future__ import annotations

import numpy as np
from pydantic import Field

from geompm.errors import CaseError
from geompm.files.atomic import case_relative, unreadable_file
from geompm.files.mesh import load_surface_mesh, mesh_signed_distance, mesh_size_problem
from geompm.obstacles.base import ObstacleParams, RigidObstacle


class RigidMeshParams(ObstacleParams):
    file: str = Field(description="Mesh file relative to the case file (STL/OBJ/PLY, watertight)")
    scale: float = Field(1.0, gt=0, description="Factor on the mesh coordinates, e.g. 0.001 for a CAD file in mm")
    rotate: list[float] = Field(default_factory=lambda: [0.0, 0.0, 0.0],
                                description="Rotation about x, y, z [deg], applied after scaling")
    translate: list[float] = Field(default_factory=lambda: [0.0, 0.0, 0.0], description="Offset [m], applied last")


class RigidMesh(RigidObstacle):
    name = "rigid_mesh"
    description = "Rigid obstacle from a watertight STL/OBJ/PLY mesh (trimesh), with force history"
    Params = RigidMeshParams

    @classmethod
    def check(cls, params, case):
        if case.dimension != 3:
            return [("type", "a mesh obstacle needs a 3D case; use box, sphere or cylinder in 2D")]
        return super().check(params, case)

    def setup(self, scene):
        import trimesh

        path = case_relative(scene.base_dir, self.params.file)
        where = f"{self.json_path}.file"
        problem = unreadable_file(path, self.params.file)
        if problem:
            raise CaseError([(where, f"mesh {problem}")])
        mesh = load_surface_mesh(path, self.params.scale, [0.0, 0.0, 0.0], where)
        for k, deg in enumerate(self.params.rotate):
            if deg:
                axis = np.eye(3)[k]
                mesh.apply_transform(trimesh.transformations.rotation_matrix(np.radians(deg), axis))
        mesh.apply_translation(np.asarray(self.params.translate, float))
        problem = mesh_size_problem(mesh, scene.grid.origin, scene.grid.upper, scene.grid.h, where,
                                    self.params.scale)
        if problem:
            raise CaseError([(f"{self.json_path}.scale", problem)])
        self.mesh = mesh
        super().setup(scene)

    def surface(self):
        from geompm.contact.tessellate import refine_triangles

        return refine_triangles(self.mesh.vertices, self.mesh.faces, self.grid.h)

    def bounds(self):
        lo, hi = self.mesh.bounds
        return np.asarray(lo, float), np.asarray(hi, float)

    def thinnest(self):
        """The mesh's thinnest part [m]: the shortest chord from a face's centre into the solid along its
        inward normal (contact/thickness.py)."""
        from geompm.contact.thickness import thinnest_part

        return thinnest_part(self.mesh.vertices, self.mesh.faces, self.mesh.face_normals)

    def signed_distance(self, pts):
        return mesh_signed_distance(self.mesh, pts)
