"""ParaView output: ``particles/particles_NNNNNN.vtu`` per output time plus ``particles.pvd``.

On several MPI ranks each rank writes its particles to ``particles/pieces/particles_NNNNNN_rankRRRR.vtu``
and rank 0 writes ``particles/particles_NNNNNN.pvtu`` over them, which the PVD lists: ParaView opens each
output time as one dataset (docs/parallel.md).

Point data (SI units): velocity (3) [m/s], displacement (3) [m],
stress (6: xx, yy, zz, xy, yz, xz) [Pa, tension positive],
mean_stress_p = -tr(sigma)/3 [Pa, compression positive], von_mises_q [Pa],
material_id, body_id, volume [m3; m2 in 2D], density [kg/m3], and every
material state variable by name (zero on particles of other materials).
2D positions get z = 0.  A case with a ``crs`` writes it into every file's
field data (``crs``, the text's ASCII codes as UInt8: add_text_field).  Files are written atomically; the PVD (a time series
index) is rewritten after each file so ParaView opens the run as an animation
even while it is still running.
"""

from __future__ import annotations

import numpy as np
from pydantic import Field

from geompm.files.atomic import atomic_path, atomic_write_text
from geompm.contract.plugin import Params
from geompm.writers.base import Writer


class VtuParams(Params):
    binary: bool = Field(True, description="Binary (zlib-compressed) VTU; false writes ASCII")


def _pad3(a):
    n, d = a.shape
    if d == 3:
        return a
    out = np.zeros((n, 3))
    out[:, :d] = a
    return out


def add_text_field(path, name: str, text: str) -> None:
    """Put ``text`` into a VTU file's FieldData as a UInt8 array of its ASCII codes, named ``name``.

    meshio writes no field data to VTU, and its reader refuses VTK's String arrays, so the text goes in
    as bytes that both meshio (``mesh.field_data[name]``) and VTK (vtkXMLUnstructuredGridReader) read:
    ``bytes(array).decode()`` gives it back.  Used for the case's CRS (docs/output-format.md)."""
    xml = path.read_text(encoding="latin-1")
    codes = " ".join(str(c) for c in text.encode("ascii"))
    block = (f'<FieldData>\n<DataArray type="UInt8" Name="{name}" NumberOfTuples="{len(text)}" format="ascii">\n'
             f"{codes}\n</DataArray>\n</FieldData>\n")
    head = "<UnstructuredGrid>\n"
    if head not in xml:
        raise ValueError(f"{path}: no <UnstructuredGrid> element to add field data to")
    path.write_text(xml.replace(head, head + block, 1), encoding="latin-1")


def particle_fields(sim) -> dict[str, np.ndarray]:
    st, sc = sim.state, sim.scene
    s = st.p_stress
    p = -(s[:, 0] + s[:, 1] + s[:, 2]) / 3.0
    dev = s[:, :3] + p[:, None]
    q = np.sqrt(1.5 * (dev ** 2).sum(axis=1) + 3.0 * (s[:, 3:] ** 2).sum(axis=1))
    fields = {
        "velocity": _pad3(st.p_v),
        "displacement": _pad3(st.p_x - st.p_x0),
        "stress": s.copy(),
        "mean_stress_p": p,
        "von_mises_q": q,
        "material_id": st.p_material.astype(np.int32),
        "body_id": st.p_body.astype(np.int32),
        # stable across the spatial sort and deletions: ParaView follows a particle by it
        # (e.g. Threshold or a Python filter on particle_id), the row order changes between outputs
        "particle_id": st.p_id.copy(),
        "volume": st.p_vol.copy(),
        "density": st.p_rho.copy(),
    }
    fields.update(sc.scheme.point_data(sim, st))  # saturated soil: "stress" is the total stress
    fields.update(sim.water.point_data(st, sim.time, p))  # under a water table: the same
    for mat, (a, b), sv in zip(sc.materials, st.blocks, st.p_state):
        for k, var in enumerate(mat.state_vars):
            arr = fields.setdefault(var, np.zeros(st.n))
            arr[a:b] = sv[:, k]
    return fields


#: VTK's names of the numpy types the particle fields take
VTK_TYPES = {"float64": "Float64", "float32": "Float32", "int64": "Int64", "int32": "Int32", "uint8": "UInt8"}


class VtuWriter(Writer):
    name = "vtu"
    files = ("particles.pvd", "particles/particles_*.vtu", "particles/particles_*.pvtu", "particles/pieces/*.vtu")
    description = "ParaView particle series: one VTU per output time and a PVD index"
    Params = VtuParams
    #: in one process one VTU per output time; on several MPI ranks each rank writes its particles as a
    #: piece and rank 0 a parallel VTU (.pvtu) that ParaView opens as one dataset (docs/parallel.md)
    ranks = "own"

    def open(self, run_dir, sim):
        self.dir = run_dir / "particles"
        self.dir.mkdir(parents=True, exist_ok=True)
        self.pvd = run_dir / "particles.pvd"
        self.entries: list[tuple[float, str]] = []
        self.root = sim.domain.comm.is_root

    def _mesh_file(self, sim, path) -> dict:
        """The particles of ``sim.state`` as a VTU at ``path``; their point data."""
        import meshio

        st = sim.state
        fields = particle_fields(sim)
        mesh = meshio.Mesh(_pad3(st.p_x), [("vertex", np.arange(st.n).reshape(-1, 1))], point_data=fields)
        with atomic_path(path) as tmp:
            meshio.write(tmp, mesh, file_format="vtu", binary=self.params.binary)
            if sim.scene.crs:
                add_text_field(tmp, "crs", sim.scene.crs)
        return fields

    def write(self, sim):
        comm = sim.domain.comm
        k = len(self.entries)
        if comm.size == 1:
            fname = f"particles_{k:06d}.vtu"
            self._mesh_file(sim, self.dir / fname)
        else:
            fname = f"particles_{k:06d}.pvtu"
            piece = f"pieces/particles_{k:06d}_rank{comm.rank:04d}.vtu"
            (self.dir / "pieces").mkdir(exist_ok=True)
            fields = self._mesh_file(sim, self.dir / piece)
            held = comm.gather(sim.state.n)
            if comm.is_root:
                names = [f"pieces/particles_{k:06d}_rank{r:04d}.vtu" for r, n in enumerate(held) if n] or [piece]
                self._write_pvtu(self.dir / fname, fields, _pad3(sim.state.p_x).dtype, names)
        self.entries.append((sim.time, f"particles/{fname}"))
        if self.root:
            self._write_pvd()

    @staticmethod
    def _write_pvtu(path, fields: dict, point_type, pieces) -> None:
        """The parallel VTU over the ranks' pieces: every point array's name, type and width, then the
        pieces in rank order (VTK's PUnstructuredGrid format)."""
        arrays = "\n".join(
            f'      <PDataArray type="{VTK_TYPES[a.dtype.name]}" Name="{name}" '
            f'NumberOfComponents="{a.shape[1] if a.ndim == 2 else 1}"/>' for name, a in fields.items())
        listed = "\n".join(f'    <Piece Source="{p}"/>' for p in pieces)
        atomic_write_text(path, '<?xml version="1.0"?>\n'
                          '<VTKFile type="PUnstructuredGrid" version="0.1" byte_order="LittleEndian">\n'
                          '  <PUnstructuredGrid GhostLevel="0">\n'
                          f'    <PPointData>\n{arrays}\n    </PPointData>\n'
                          f'    <PPoints>\n      <PDataArray type="{VTK_TYPES[np.dtype(point_type).name]}" '
                          'NumberOfComponents="3"/>\n    </PPoints>\n'
                          f'{listed}\n  </PUnstructuredGrid>\n</VTKFile>\n')

    def _write_pvd(self):
        rows = "\n".join(f'    <DataSet timestep="{t:.10g}" group="" part="0" file="{f}"/>'
                         for t, f in self.entries)
        atomic_write_text(self.pvd, '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
                          f"  <Collection>\n{rows}\n  </Collection>\n</VTKFile>\n")

    def state(self):
        return {"entries": [list(e) for e in self.entries]}

    def resume(self, run_dir, sim, state):
        """Keep the files listed at the checkpoint; later ones are overwritten as the run repeats them."""
        self.open(run_dir, sim)
        self.entries = [tuple(e) for e in state["entries"]]
        if self.root:
            self._write_pvd()
