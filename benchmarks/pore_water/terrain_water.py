"""cases/terrain_debris_flow.json with saturated debris, as the issue's new user ran it (n = 0.4, k = 1e-4 m/s):
the pore-pressure-ratio map along the path (docs/pore-water.md, Outputs; the hazard maps' basal ratio
lambda = p_b / sigma_b), against the dry case's footprint.

The debris keeps the shipped case's saturated density (2 000 kg/m3: grains rho_s = 2 667 kg/m3) and takes
the main job's saturated parameters: phi = 30 degrees (the grains' friction; the dry case's 18 degrees
stands in for the water's effect), K_w = 2e7 Pa (reduced as in the main job), friction on the terrain and
the dam on effective stress.  The water table at the release's top (hydrostatic below it).

    python benchmarks/pore_water/terrain_water.py OUT_DIR [END_S] [--dry]

Writes OUT_DIR/{wet|dry}/ (the run's folder with maps/) and prints a JSON summary: the peak ratio, its
percentiles over the impact area, the share of the impact area where the ratio stayed 0, the ratio along
the path in 20 m bands of x, the front's x and the wall time.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

from geompm.api import run
from geompm.testing.verification.cases import shipped_case

CASE = shipped_case("terrain_debris_flow.json")


def wet_case(end: float, dry: bool) -> dict:
    case = json.loads(CASE.read_text())
    here = CASE.parent
    geo = case["bodies"][0]["geometry"]
    geo["file"], geo["dem"] = str(here / geo["file"]), str(here / geo["dem"])
    for ob in case["obstacles"]:
        for key in ("dem", "file"):
            if key in ob:
                ob[key] = str(here / ob[key])
    case["time"]["end"] = end
    case["outputs"] = [o for o in case["outputs"] if o["writer"] in ("series", "hazard_maps")]
    if dry:
        return case
    soil = case["materials"]["debris"]
    n = 0.4
    soil.update(density=(soil["density"] - n * 1000.0) / (1 - n), friction_angle=30.0,
                pore_water={"porosity": n, "hydraulic_conductivity": 1e-4,
                            "fluid": {"density": 1000.0, "bulk_modulus": 2e7, "viscosity": 1e-3}})
    case["solver"] = {"transfer": "apic", "update": "saturated"}
    case["time"]["cfl"] = 0.1
    return case


def summary(run_dir: Path) -> dict:
    import rasterio

    maps = run_dir / "maps"
    out = json.loads((maps / "summary.json").read_text())
    with rasterio.open(maps / "depth_max.tif") as src:
        depth = src.read(1)
        x0, dx = src.transform.c, src.transform.a
    impact = depth >= 0.1
    out["impact_cells"] = int(impact.sum())
    ratio_file = maps / "pore_pressure_ratio_max.tif"
    if ratio_file.exists():
        with rasterio.open(ratio_file) as src:
            ratio = src.read(1)
        r = ratio[impact]
        out["ratio_percentiles_5_50_95_max"] = [float(np.percentile(r, q)) for q in (5, 50, 95, 100)]
        out["ratio_zero_share"] = float((r <= 0.0).mean())
        out["ratio_above_one_cells"] = int((r > 1.0).sum())
        cols = np.arange(depth.shape[1])
        xs = x0 + (cols + 0.5) * dx
        bands = {}
        for lo in range(0, int(xs.max() - x0), 20):
            sel = impact & ((xs - x0 >= lo) & (xs - x0 < lo + 20))[None, :]
            if sel.any():
                bands[f"{lo}-{lo + 20} m"] = [int(sel.sum()), float(np.median(ratio[sel])), float(ratio[sel].max())]
        out["ratio_by_x_band_cells_median_max"] = bands
    return out


def main(argv) -> None:
    out_dir = Path(argv[0])
    end = float(argv[1]) if len(argv) > 1 and not argv[1].startswith("--") else 40.0
    dry = "--dry" in argv
    run_dir = out_dir / ("dry" if dry else "wet")
    t0 = time.perf_counter()
    out_dir.mkdir(parents=True, exist_ok=True)
    case_file = out_dir / f"{run_dir.name}.json"
    case_file.write_text(json.dumps(wet_case(end, dry), indent=1))
    run(case_file, out=run_dir, progress=False, quiet=True)
    result = {"case": "dry" if dry else "wet", "end": end, "wall_s": round(time.perf_counter() - t0, 1),
              **summary(run_dir)}
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    main(sys.argv[1:])
