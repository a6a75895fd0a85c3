"""HDF5 results: ``results.h5`` plus one fields file per output time (layout: docs/output-format.md).

``results.h5`` (the file to open) holds, as attributes, the geompm and plugin
versions, the numba thread count, the dimension and the resolved case JSON;
``series/<column>`` datasets with every row of series.csv so far; the output
``times`` and ``steps``; and ``particles/NNNNNN``, an HDF5 external link to
``results/particles_NNNNNN.h5``, whose root holds the particle fields of one
output time (the VTU fields: position, velocity, displacement, stress,
mean_stress_p, von_mises_q, ids, volume, density, state variables), chunked
and gzip-compressed, with ``time`` and ``step`` attributes.  Plain h5py
follows the links: ``h5py.File("results.h5")["particles/000003/velocity"]``.

Every file is written under a temporary name, fsynced and renamed (files/atomic.py),
so a killed run leaves only complete files: the index names only fields files
that exist.  Rewriting the small index at each output keeps the cost per output
independent of the run's length.
"""

from __future__ import annotations

import json
from importlib import metadata
from pathlib import Path

import numpy as np
from pydantic import Field

from geompm.contract import registry
from geompm.version import __version__
from geompm.files.atomic import atomic_path
from geompm.contract.plugin import Params
from geompm.writers.base import Writer
from geompm.writers.vtu import _pad3, particle_fields


class Hdf5Params(Params):
    compression: int = Field(4, ge=0, le=9, description="gzip level of the particle fields (0: none)")


def _plugin_versions() -> dict[str, str]:
    out = {}
    for kind in registry.GROUPS:
        for info in registry.available(kind).values():
            try:
                out[info.package] = metadata.version(info.package)
            except metadata.PackageNotFoundError:
                out[info.package] = "unknown"
    return out


class Hdf5Writer(Writer):
    name = "hdf5"
    files = ("results.h5", "results/particles_*.h5")
    description = "HDF5 results: series, particle fields per output time, case and versions (h5py)"
    Params = Hdf5Params

    def open(self, run_dir, sim):
        self.run_dir = Path(run_dir)
        (self.run_dir / "results").mkdir(parents=True, exist_ok=True)
        self.outputs: list[tuple[float, int, str]] = []
        self.series_offset = 0
        self.series_cols: list[str] = []
        self.series_rows: list[np.ndarray] = []

    def _read_series(self):
        """New complete rows of series.csv since the last call."""
        path = self.run_dir / "series.csv"
        if not path.is_file():
            return
        with open(path, "rb") as fh:
            fh.seek(self.series_offset)
            chunk = fh.read()
        end = chunk.rfind(b"\n") + 1
        lines = chunk[:end].decode().splitlines()
        self.series_offset += end
        if lines and not self.series_cols:
            self.series_cols, lines = lines[0].split(","), lines[1:]
        if lines:
            self.series_rows.append(np.array([[float(v) for v in ln.split(",")] for ln in lines]).reshape(
                len(lines), len(self.series_cols)))

    def _write_fields(self, sim, fname):
        import h5py

        st = sim.state
        fields = {"position": _pad3(st.p_x), **particle_fields(sim)}
        comp = {"compression": "gzip", "compression_opts": self.params.compression, "shuffle": True} \
            if self.params.compression else {}
        with atomic_path(self.run_dir / "results" / fname) as tmp:
            with h5py.File(tmp, "w") as f:
                f.attrs["time"] = sim.time
                f.attrs["step"] = sim.step_count
                for name, arr in fields.items():
                    chunks = (min(len(arr), 65536),) + arr.shape[1:] if len(arr) else None
                    f.create_dataset(name, data=arr, chunks=chunks, **(comp if len(arr) else {}))

    def _write_index(self, sim):
        import h5py
        import numba

        with atomic_path(self.run_dir / "results.h5") as tmp:
            with h5py.File(tmp, "w") as f:
                f.attrs["geompm_version"] = __version__
                f.attrs["plugin_versions"] = json.dumps(_plugin_versions())
                f.attrs["threads"] = numba.get_num_threads()
                f.attrs["dimension"] = sim.scene.dim
                f.attrs["case"] = sim.scene.case_text
                f.attrs["units"] = "SI: m, s, kg, Pa, N (N/m in 2D plane strain), J (J/m in 2D)"
                f.attrs["crs"] = sim.scene.crs or ""  # the case's coordinate reference system, '' if none
                f["times"] = np.array([o[0] for o in self.outputs], float)
                f["steps"] = np.array([o[1] for o in self.outputs], np.int64)
                grp = f.create_group("series")
                rows = np.concatenate(self.series_rows) if self.series_rows else np.zeros((0, len(self.series_cols)))
                for k, col in enumerate(self.series_cols):
                    grp[col] = rows[:, k].astype(np.int64) if col == "step" else rows[:, k]
                parts = f.create_group("particles")
                for k, (_, _, fname) in enumerate(self.outputs):
                    parts[f"{k:06d}"] = h5py.ExternalLink(f"results/{fname}", "/")

    def write(self, sim):
        fname = f"particles_{len(self.outputs):06d}.h5"
        self._write_fields(sim, fname)
        self.outputs.append((sim.time, sim.step_count, fname))
        self._read_series()
        self._write_index(sim)

    def close(self, sim):
        self._read_series()  # the series rows written after the last output
        if self.outputs:
            self._write_index(sim)

    def state(self):
        return {"outputs": [list(o) for o in self.outputs]}

    def resume(self, run_dir, sim, state):
        """Keep the outputs listed at the checkpoint; the series is re-read from the (cut) series.csv."""
        self.open(run_dir, sim)
        self.outputs = [(float(t), int(s), str(f)) for t, s, f in state["outputs"]]
