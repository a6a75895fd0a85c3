"""ParaView output of the rigid surfaces: ``surfaces/<label>_NNNNNN.vtu`` per output time plus ``surfaces.pvd``.

Every boundary and obstacle stage that has a surface (Stage.surface: STL and
analytic obstacles, planes and walls clipped to the grid, the terrain) is
written in the particles' coordinates, moved by its prescribed velocity
(Stage.surface_shift), one VTU per stage and output time.  The PVD lists the
stages of one time as parts of a multiblock, at the same times as
``particles.pvd``, so ParaView opens the particles and the surfaces side by
side as one animation.  Cells are triangles in 3D and lines in 2D (the
outline in the x-y plane, per metre of depth).  Cell data: ``normal`` (3, unit,
out of the solid for obstacles; triangles otherwise from the vertex order,
lines the in-plane normal) and ``stage_id``; on every obstacle (and the
terrain) the contact force of the output's step spread on the faces
(recorded.ContactForceStage.start_faces): ``traction`` (3) [Pa], the force of
the material on the face per unit area, normal and shear together, whose
integral over the surface (ParaView's Integrate Variables; per metre of depth
in 2D) is the obstacle's force in series.csv at that step; ``normal_pressure``
[Pa, pushing in positive], ``shear_traction`` [Pa, its tangential part's
magnitude], and over the run so far
``max_normal_pressure`` [Pa] and ``time_of_max`` [s], and ``pressure_at_peak_force``
[Pa], the normal pressure at the step of the largest |F| so far.  A surface that
neither moves nor carries pressures is written once and listed at every
time (its file is the same).
"""

from __future__ import annotations

import numpy as np
from pydantic import Field

from geompm.files.atomic import atomic_path, atomic_write_text
from geompm.contract.plugin import Params
from geompm.writers.base import Writer
from geompm.writers.vtu import add_text_field


class SurfacesParams(Params):
    binary: bool = Field(True, description="Binary (zlib-compressed) VTU; false writes ASCII")


class SurfacesWriter(Writer):
    name = "surfaces"
    files = ("surfaces.pvd", "surfaces/*.vtu")
    description = "ParaView series of every rigid surface (obstacles, planes, walls, terrain): VTU per time and a PVD"
    Params = SurfacesParams
    wants_face_forces = True
    ranks = "none"  # the surfaces and their face pressures are the same on every rank

    def open(self, run_dir, sim):
        self.dir = run_dir / "surfaces"
        self.dir.mkdir(parents=True, exist_ok=True)
        self.pvd = run_dir / "surfaces.pvd"
        sc = sim.scene
        self.parts = [(s.label, s, s.surface()) for s in sc.stages]
        self.parts = [(label, s, surf) for label, s, surf in self.parts if surf is not None]
        self.entries: list[tuple[float, list[str]]] = []
        self.static: dict[str, str] = {}  # label -> the file of a surface that does not move

    def write(self, sim):
        k = len(self.entries)
        files = []
        for sid, (label, stage, surf) in enumerate(self.parts):
            shift = stage.surface_shift(sim.time)
            loaded = stage.faces is not None  # its pressures change: written every time
            if shift is None and not loaded and label in self.static:
                files.append(self.static[label])
                continue
            fname = f"surfaces/{label}_{k:06d}.vtu"
            self._write_mesh(self.dir.parent / fname, surf, shift, sid, stage if loaded else None, sim.scene.crs)
            if shift is None and not loaded:
                self.static[label] = fname
            files.append(fname)
        self.entries.append((sim.time, files))
        self._write_pvd()

    def _write_mesh(self, path, surf, shift, sid, loaded, crs=None):
        import meshio

        pts = surf.vertices.copy()
        if shift is not None:
            pts[:, : len(shift)] += shift
        cell = {"stage_id": np.full(len(surf.cells), sid, np.int32), "normal": surf.normals()}
        if loaded is not None:
            n = np.zeros((len(surf.cells), 3))
            n[:, :loaded.dim] = loaded.face_normal
            traction = np.zeros((len(surf.cells), 3))
            traction[:, :loaded.dim] = loaded.face_force / loaded.face_area[:, None]
            cell.update(normal=n, traction=traction, normal_pressure=loaded.face_pressure.copy(), shear_traction=loaded.face_shear.copy(),
                        max_normal_pressure=loaded.face_pmax.copy(), time_of_max=loaded.face_tmax.copy(),
                        pressure_at_peak_force=loaded.face_p_at_peak.copy())
        mesh = meshio.Mesh(pts, [(surf.kind, surf.cells)], cell_data={k: [v] for k, v in cell.items()})
        with atomic_path(path) as tmp:
            meshio.write(tmp, mesh, file_format="vtu", binary=self.params.binary)
            if crs:
                add_text_field(tmp, "crs", crs)

    def _write_pvd(self):
        rows = "\n".join(f'    <DataSet timestep="{t:.10g}" group="" part="{p}" file="{f}"/>'
                         for t, files in self.entries for p, f in enumerate(files))
        atomic_write_text(self.pvd, '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
                          f"  <Collection>\n{rows}\n  </Collection>\n</VTKFile>\n")

    def state(self):
        return {"entries": [[t, list(f)] for t, f in self.entries], "static": dict(self.static)}

    def resume(self, run_dir, sim, state):
        """Keep the files listed at the checkpoint; later ones are overwritten as the run repeats them."""
        self.open(run_dir, sim)
        self.entries = [(t, list(f)) for t, f in state["entries"]]
        self.static = dict(state.get("static", {}))
        self._write_pvd()
