"""Hazard maps on the DEM's raster, written as GeoTIFF with the DEM's CRS and transform (3D cases).

Every step (whatever the output's ``interval``) the particles are binned by
their (x, y) into the DEM's pixels (the terrain obstacle's DEM, or the file
``dem`` names; ``coarsen`` merges k x k pixels), and per pixel of area A:

    flow depth      h = sum V0_p / A                 [m]   (the particles' reference volumes
                                                            m_p / rho0: the vertical thickness the
                                                            material over the pixel would have at its
                                                            reference density; a flow that loosens
                                                            or separates does not thicken the map)
    speed           |u|, u = sum m_p v_p / sum m_p   [m/s] (the column's mass-weighted velocity)
    pressure        rho u^2, rho = sum m_p / sum V0_p [Pa] (dynamic pressure of the column)
    kinetic energy  sum m_p |v_p|^2 / (2 A)          [J/m2]

With saturated soil (docs/pore-water.md) one more map, ``pore_pressure_ratio_max``: the largest over the
run of the basal pore-pressure ratio lambda = p_b / sigma_b of each column at least ``depth_threshold``
deep, p_b the pore pressure of the column's lowest particle and sigma_b = g sum (m_s + m_w) / A the
column's total weight per area (Iverson 1997: lambda near 1 is a liquefied, far-running flow).

The maps kept are the maxima over the run of each (``depth_max``,
``speed_max``, ``pressure_max``, ``energy_max``), the first time the depth
reached ``depth_threshold`` while the column moved at ``arrival_speed`` or faster (``arrival``: a deposit
that creeps into a cell after the flow stopped does not arrive there; the source's cells arrive at the
start), the
depth at the end (``deposit``) and at the start (``source``); with ``times`` the depth and speed at each of
those times (``depth_t<time>``, ``speed_t<time>``: the depth and the speed a barrier sees at one moment);
every map is NoData (-9999) where its quantity is not defined: outside the flow (the depth never reached
the threshold) for the maxima and the arrival, outside the deposit and the source (thinner than the
threshold) for those, outside the flow at that time for the timed maps.  Each band's description
names the quantity and its unit (``depth_max [m]``); the names
follow practice (r.avaflow's hflow_max, vflow_max, pflow_max, treach,
hflow_dep).  The speed, pressure and energy maxima count only columns at
least ``depth_threshold`` deep (a lone particle's speed is not a flow's).
Particles outside the raster are counted in ``volume_outside_m3`` of
``maps/summary.json``, with the impact area (cells that reached the threshold),
the source and deposit volumes, the peak pressure and speed, and the travel:
the horizontal distance L from the top of the release (its highest cell,
ground plus release depth) to the farthest cell the flow reached, the drop
H between them and the travel angle atan(H / L) (`geompm info` prints them), and the runout along the
thalweg from that top (the line of steepest descent, writers/thalweg.py) to the last of its cells the
flow reached.  Files: ``maps/<name>.tif`` (float64, NoData -9999), written at
the end and at every checkpoint, each atomically; the accumulated state at a
checkpoint goes to ``maps/state.npz`` so a resumed run carries on.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from numba import njit
from pydantic import Field

from geompm.contract import registry
from geompm.errors import CaseError
from geompm.files.atomic import atomic_path, atomic_write_json, case_relative
from geompm.contract.plugin import Params
from geompm.writers.base import Writer
from geompm.writers.thalweg import runout_along, thalweg

NODATA = -9999.0
MAPS = ("depth_max", "speed_max", "pressure_max", "energy_max", "arrival", "deposit", "source")
#: maps that are NoData where the flow never reached the depth threshold
FLOW_MAPS = ("depth_max", "speed_max", "pressure_max", "energy_max", "pore_pressure_ratio_max")


class HazardMapParams(Params):
    dem: str | None = Field(None, description="Raster whose pixels the maps use (GeoTIFF / ESRI ASCII, relative to "
                                              "the case file); default the terrain obstacle's DEM")
    coarsen: int = Field(1, ge=1, description="Merge k x k pixels of the raster into one map cell")
    depth_threshold: float = Field(0.01, gt=0, description="Depth [m] that counts as flow (arrival, maxima)")
    arrival_speed: float = Field(0.1, ge=0, description="Speed [m/s] a column must move at for the flow to arrive "
                                                        "there (the deposit's creep does not); 0: any")
    times: list[float] = Field(default_factory=list, description="Times [s] at which the depth and speed maps are "
                                                                 "written (depth_t<time>.tif, speed_t<time>.tif)")


@njit(cache=True)
def column_sums(p_x, p_v, p_mass, p_vol, x0, y0, cx, cy, nx, ny, out):
    """Per map cell: out[i, j] = (sum V, sum m, sum m v_x, sum m v_y, sum m v_z, sum m |v|^2); cells of
    size cx x cy [m] from the corner (x0, y0).  Returns the volume outside the map."""
    out[:] = 0.0
    outside = 0.0
    for p in range(p_x.shape[0]):
        i = int(np.floor((p_x[p, 0] - x0) / cx))
        j = int(np.floor((p_x[p, 1] - y0) / cy))
        if i < 0 or j < 0 or i >= nx or j >= ny:
            outside += p_vol[p]
            continue
        m = p_mass[p]
        out[i, j, 0] += p_vol[p]
        out[i, j, 1] += m
        v2 = 0.0
        for a in range(3):
            out[i, j, 2 + a] += m * p_v[p, a]
            v2 += p_v[p, a] * p_v[p, a]
        out[i, j, 5] += m * v2
    return outside


@njit(cache=True)
def accumulate(sums, area, threshold, arrival_speed, time, depth, speed, depth_max, speed_max, pressure_max,
               energy_max, arrival):
    nx, ny = depth.shape
    for i in range(nx):
        for j in range(ny):
            vol, m = sums[i, j, 0], sums[i, j, 1]
            h = vol / area
            depth[i, j] = h
            speed[i, j] = 0.0
            if h > depth_max[i, j]:
                depth_max[i, j] = h
            if h < threshold or m <= 0.0:
                continue
            u2 = (sums[i, j, 2] ** 2 + sums[i, j, 3] ** 2 + sums[i, j, 4] ** 2) / (m * m)
            speed[i, j] = np.sqrt(u2)
            if arrival[i, j] < 0.0 and speed[i, j] >= arrival_speed:
                arrival[i, j] = time
            speed_max[i, j] = max(speed_max[i, j], np.sqrt(u2))
            pressure_max[i, j] = max(pressure_max[i, j], m / vol * u2)
            energy_max[i, j] = max(energy_max[i, j], 0.5 * sums[i, j, 5] / area)



@njit(cache=True)
def basal_ratio(p_x, p_pore, p_wet_mass, x0, y0, cx, cy, nx, ny, area, g, depth, threshold, ratio_max, work):
    """Per map cell: the pore pressure of the lowest particle over the column's total weight per area
    (p_wet_mass: solids and water of each particle [kg]); the largest so far kept in ratio_max.  ``work``
    (nx, ny, 3): lowest z, its pore pressure, the column's mass."""
    for i in range(nx):
        for j in range(ny):
            work[i, j, 0] = np.inf
            work[i, j, 1] = 0.0
            work[i, j, 2] = 0.0
    for p in range(p_x.shape[0]):
        i = int(np.floor((p_x[p, 0] - x0) / cx))
        j = int(np.floor((p_x[p, 1] - y0) / cy))
        if i < 0 or j < 0 or i >= nx or j >= ny:
            continue
        work[i, j, 2] += p_wet_mass[p]
        if p_x[p, 2] < work[i, j, 0]:
            work[i, j, 0] = p_x[p, 2]
            work[i, j, 1] = p_pore[p]
    for i in range(nx):
        for j in range(ny):
            if depth[i, j] >= threshold and work[i, j, 2] > 0.0:
                ratio_max[i, j] = max(ratio_max[i, j], work[i, j, 1] / (g * work[i, j, 2] / area))


def _provides_ground(obstacle_type: str) -> bool:
    """Whether the obstacle plugin ``obstacle_type`` declares itself a ground (Stage.provides_ground)."""
    plugin = registry.available("obstacles").get(obstacle_type)
    return plugin is not None and plugin.plugin.provides_ground


class HazardMapWriter(Writer):
    name = "hazard_maps"
    files = ("maps/*.tif", "maps/summary.json")
    description = "GeoTIFF hazard maps on the DEM: max depth, speed, pressure, energy, arrival time, deposit (3D)"
    Params = HazardMapParams
    ranks = "own"  # the column sums are summed over the ranks; rank 0 writes the maps

    def __init__(self, params, interval: float):
        super().__init__(params, 0.0)  # accumulated every step, whatever the output interval

    @classmethod
    def check(cls, params, case):
        if case.dimension != 3:
            return [("writer", "hazard maps need a 3D case (maps of a surface z = H(x, y))")]
        if params.dem is None and not any(_provides_ground(o.type) for o in case.obstacles):
            return [("dem", "no raster for the maps: add a terrain obstacle or give 'dem' (a GeoTIFF)")]
        return []

    def _raster(self, sim):
        from geompm.files.dem import read_dem

        if self.params.dem is not None:
            self.dem_path = case_relative(sim.scene.base_dir, self.params.dem)
            return read_dem(self.dem_path, "outputs: hazard_maps.dem")
        for stage in sim.scene.stages:
            if stage.provides_ground:
                self.dem_path, where = stage.ground_dem()
                return read_dem(self.dem_path, where)
        raise CaseError([("outputs", "hazard_maps needs a raster: add a terrain obstacle or give 'dem'")])

    def open(self, run_dir: Path, sim) -> None:
        dem = self._raster(sim)
        k = self.params.coarsen
        nx, ny = dem.z.shape[0] // k, dem.z.shape[1] // k
        if nx < 1 or ny < 1:
            raise CaseError([("outputs", f"hazard_maps.coarsen = {k} leaves no map cell on a "
                                         f"{dem.z.shape[0]} x {dem.z.shape[1]} raster")])
        self.crs = dem.crs
        self.dem = dem
        self.cx, self.cy = dem.dx * k, dem.dy * k
        self.x0, self.y0 = dem.x0 - dem.dx / 2, dem.y0 - dem.dy / 2  # the raster's corner (pixel edges)
        self.area = self.cx * self.cy
        self.folder = Path(run_dir) / "maps"
        self.root = sim.domain.comm.is_root
        if self.root:
            self.folder.mkdir(exist_ok=True)
        self.sums = np.zeros((nx, ny, 6))
        self.depth = np.zeros((nx, ny))
        self.speed = np.zeros((nx, ny))  # the column's speed now [m/s] (0 below the threshold)
        self.maps = {name: np.zeros((nx, ny)) for name in MAPS}
        self.timed = sorted(self.params.times)  # times still to write [s]
        self.maps["arrival"][:] = -1.0
        self.basal = None
        if sim.scene.scheme.pore_water:  # the scheme carries pore water: its basal ratio is mapped
            self.maps["pore_pressure_ratio_max"] = np.zeros((nx, ny))
            self.basal = np.zeros((nx, ny, 3))
        self.started = False
        self.volume_outside = 0.0
        self.written_times = {}  # timed maps written: the asked time -> the step's time [s]

    def write(self, sim) -> None:
        st = sim.state
        nx, ny = self.depth.shape
        outside = column_sums(st.p_x, st.p_v, st.p_mass, st.p_vol0, self.x0, self.y0, self.cx, self.cy, nx, ny,
                              self.sums)
        comm = sim.domain.comm
        self.sums[:] = comm.sum(self.sums)
        self.volume_outside = float(comm.sum([outside])[0])
        m = self.maps
        if not self.started:  # the source has arrived where it starts, moving or not
            m["arrival"][self.sums[:, :, 0] / self.area >= self.params.depth_threshold] = sim.time
        accumulate(self.sums, self.area, self.params.depth_threshold, self.params.arrival_speed, sim.time,
                   self.depth, self.speed, m["depth_max"], m["speed_max"], m["pressure_max"], m["energy_max"],
                   m["arrival"])
        while self.timed and sim.time >= self.timed[0] - 1e-12 * max(1.0, self.timed[0]):
            self._timed_maps(self.timed.pop(0), sim.time)
        if self.basal is not None:
            pore, wet_mass, g = sim.scene.scheme.basal_water(st)
            basal_ratio(st.p_x, pore, wet_mass, self.x0, self.y0, self.cx, self.cy, nx, ny, self.area,
                        g, self.depth, self.params.depth_threshold, m["pore_pressure_ratio_max"],
                        self.basal)
        if not self.started:
            m["source"][:] = self.depth
            self.started = True
        m["deposit"][:] = self.depth

    def _write_tif(self, name: str, data, unit: str) -> None:
        import rasterio
        from rasterio.transform import Affine

        nx, ny = data.shape
        transform = Affine(self.cx, 0.0, self.x0, 0.0, -self.cy, self.y0 + ny * self.cy)  # north-up
        band = data.T[::-1]  # rows from north to south
        with atomic_path(self.folder / f"{name}.tif") as tmp:
            with rasterio.open(tmp, "w", driver="GTiff", height=ny, width=nx, count=1, dtype="float64",
                               crs=self.crs, transform=transform, nodata=NODATA) as dst:
                dst.write(band, 1)
                dst.set_band_description(1, f"{name} [{unit}]")
                dst.update_tags(1, quantity=name, units=unit)

    def _masked(self, name: str, grid):
        """The map with NoData where its quantity is not defined (the module's docstring)."""
        t = self.params.depth_threshold
        data = grid.copy()
        if name == "arrival":
            data[data < 0.0] = NODATA
        elif name in FLOW_MAPS:
            data[self.maps["depth_max"] < t] = NODATA
        elif name in ("deposit", "source"):
            data[grid < t] = NODATA
        return data

    def _timed_maps(self, when: float, now: float) -> None:
        """depth_t<when>.tif and speed_t<when>.tif of the state at ``now`` (the first step at or after it)."""
        if not self.root:
            return
        flowing = self.depth >= self.params.depth_threshold
        tag = f"{when:g}"
        self._write_tif(f"depth_t{tag}", np.where(flowing, self.depth, NODATA), "m")
        self._write_tif(f"speed_t{tag}", np.where(flowing, self.speed, NODATA), "m/s")
        self.written_times[tag] = now

    def _geotiffs(self):
        for name, grid in self.maps.items():
            self._write_tif(name, self._masked(name, grid), UNITS[name])

    def close(self, sim) -> None:
        if not self.root:
            return
        self._geotiffs()
        m = self.maps
        flowed = m["depth_max"] >= self.params.depth_threshold
        reached = m["arrival"] >= 0.0
        summary = {"impact_area_m2": float(flowed.sum() * self.area),
                   "deposit_volume_m3": float(m["deposit"].sum() * self.area),
                   "source_volume_m3": float(m["source"].sum() * self.area),
                   "volume_outside_m3": float(self.volume_outside),
                   "last_arrival_s": float(m["arrival"][reached].max()) if reached.any() else None,
                   "peak_pressure_Pa": float(m["pressure_max"].max()), "peak_speed_m_s": float(m["speed_max"].max()),
                   **({"peak_pore_pressure_ratio": float(m["pore_pressure_ratio_max"].max())}
                      if "pore_pressure_ratio_max" in m else {}),
                   "crs": self.crs, "depth_threshold": self.params.depth_threshold,
                   "arrival_speed": self.params.arrival_speed, "timed_maps": self.written_times,
                   "dem": str(self.dem_path.resolve())}
        summary.update(self._travel(flowed))
        atomic_write_json(self.folder / "summary.json", summary, indent=1)

    def _travel(self, flowed) -> dict:
        """Runout along the ground from the release's top to the farthest cell the flow reached (depth >=
        threshold), its drop H and the travel angle atan(H / L) (the Fahrboeschung of practice)."""
        src = self.maps["source"] > 0.0
        if not src.any() or not flowed.any():
            return {"runout_length_m": None, "drop_height_m": None, "travel_angle_deg": None,
                    "runout_thalweg_m": None}
        nx, ny = self.depth.shape
        cx = self.x0 + (np.arange(nx) + 0.5) * self.cx
        cy = self.y0 + (np.arange(ny) + 0.5) * self.cy
        X, Y = np.meshgrid(cx, cy, indexing="ij")
        ground = self.dem.height(X.ravel(), Y.ravel()).reshape(X.shape)
        top = np.unravel_index(np.argmax(np.where(src, ground + self.maps["source"], -np.inf)), src.shape)
        dist = np.hypot(X - X[top], Y - Y[top])
        far = np.unravel_index(np.argmax(np.where(flowed, dist, -1.0)), dist.shape)
        length = float(dist[far])
        drop = float(ground[top] + self.maps["source"][top] - ground[far])
        angle = math.degrees(math.atan2(drop, length)) if length > 0 else None
        path, along = thalweg(ground, self.cx, self.cy, top)
        return {"runout_length_m": length, "drop_height_m": drop, "travel_angle_deg": angle,
                "runout_thalweg_m": runout_along(path, along, flowed),
                "thalweg_end": [float(X[path[-1]]), float(Y[path[-1]])]}

    def state(self) -> dict:
        self._geotiffs()
        with atomic_path(self.folder / "state.npz") as tmp:
            with open(tmp, "wb") as fh:
                np.savez(fh, **self.maps)
        return {"started": self.started, "timed": self.timed, "written_times": self.written_times}

    def resume(self, run_dir: Path, sim, state: dict) -> None:
        self.open(run_dir, sim)
        saved = np.load(self.folder / "state.npz")
        for name in self.maps:
            self.maps[name][:] = saved[name]
        self.started = bool(state.get("started", True))
        self.timed = list(state.get("timed", self.timed))
        self.written_times = dict(state.get("written_times", {}))


UNITS = {"depth_max": "m", "speed_max": "m/s", "pressure_max": "Pa", "energy_max": "J/m2", "arrival": "s",
         "deposit": "m", "source": "m", "pore_pressure_ratio_max": "-"}
