"""Peak memory of `geompm validate` on a 2 km site against the run's own estimate (docs/terrain.md).

A synthetic valley in EPSG:32632: a 2 x 2 km DEM at 2 m pixels rising 400 m across (heights 500-900 m), a
30 x 30 m release 1.5 m deep (1 350 m3) in its middle, the grid over the release's neighbourhood and the
whole relief (so the release's bounding box spans 400 m of height, as a site's does).  For each cell size it
runs `geompm validate` in a fresh process and prints the peak resident memory (ru_maxrss of the child) beside
the estimate validate prints (the arrays plus the process), then, with --run, runs 0.02 s of the case and
prints the run's peak (status.json's peak_rss_bytes).

    python benchmarks/terrain/validate_memory.py 1.0 0.5 0.25
"""

from __future__ import annotations

import json
import re
import time
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

W, S = 500_000.0, 5_200_000.0  # UTM 32N [m]


def site(folder: Path) -> Path:
    import rasterio
    from rasterio.transform import Affine

    n, dx = 1000, 2.0
    xs = W + (np.arange(n) + 0.5) * dx
    X, _ = np.meshgrid(xs, np.arange(n))
    z = 500.0 + 400.0 * (X - W) / 2000.0
    with rasterio.open(folder / "dem.tif", "w", driver="GTiff", height=n, width=n, count=1, dtype="float64",
                       crs="EPSG:32632", transform=Affine(dx, 0, W, 0, -dx, S + n * dx), nodata=-9999.0) as dst:
        dst.write(z, 1)
    ring = [[W + 985, S + 985], [W + 1015, S + 985], [W + 1015, S + 1015], [W + 985, S + 1015], [W + 985, S + 985]]
    (folder / "release.geojson").write_text(json.dumps({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [ring]}}]}))
    case = {"name": "site2km", "dimension": 3, "crs": "EPSG:32632",
            "grid": {"origin": [W + 900, S + 900, 490.0], "extent": [200.0, 200.0, 420.0], "cell_size": 1.0},
            "time": {"end": 1.0}, "gravity": [0, 0, -9.81],
            "materials": {"debris": {"model": "drucker_prager", "density": 2000.0, "youngs_modulus": 2e6,
                                     "poisson_ratio": 0.3, "friction_angle": 30.0, "cohesion": 0.0}},
            "bodies": [{"material": "debris", "particles_per_cell": 2,
                        "geometry": {"type": "release_polygon", "file": "release.geojson", "dem": "dem.tif",
                                     "thickness": 1.5}}],
            "obstacles": [{"type": "terrain", "name": "ground", "dem": "dem.tif", "friction": 0.3}]}
    path = folder / "site.json"
    path.write_text(json.dumps(case))
    return path


def main() -> int:
    run = "--run" in sys.argv
    sizes = [float(a) for a in sys.argv[1:] if a != "--run"] or [1.0, 0.5]
    with tempfile.TemporaryDirectory() as tmp:
        case = site(Path(tmp))
        print("h [m]  particles  validate's estimate  peak RSS of validate  wall [s]" + ("  run's peak RSS" if run else ""))
        for h in sizes:
            child = ("import resource, sys; from geompm.cli.main import main; rc = main(sys.argv[1:]); "
                     "print('PEAK', resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)")
            t0 = time.perf_counter()
            out = subprocess.run([sys.executable, "-c", child, "validate", str(case), "--set", f"grid.cell_size={h}"],
                                 capture_output=True, text=True)
            wall = time.perf_counter() - t0
            text = out.stdout + out.stderr
            est = re.search(r"(estimated memory [\d.]+ MiB)", text)
            parts = re.search(r"3D, (\d+) particles", text)
            peak = re.search(r"PEAK (\d+)", text)
            line = (f"{h:<6} {parts.group(1) if parts else '-':<10} {est.group(1) if est else text.strip()[-200:]:<20} "
                    f"{int(peak.group(1)) / 1024 if peak else float('nan'):<20.0f} {wall:.1f}")
            if run:
                folder = Path(tmp) / f"run{h}"
                subprocess.run([sys.executable, "-m", "geompm.cli", "run", str(case), "--set", f"grid.cell_size={h}",
                                "--set", "time.end=0.02", "--out", str(folder), "--quiet"], capture_output=True, text=True)
                status = json.loads((folder / "status.json").read_text())
                line += f"  {status['peak_rss_bytes'] / 2**20:.0f} MiB ({status['steps']} steps)"
            print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
