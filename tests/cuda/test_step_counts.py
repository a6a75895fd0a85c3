"""What an ordinary CUDA step asks of the host (geompm/bench/cuda_counts.py, benchmarks/device/count_launches.py),
counted under numba-cuda's simulator in a subprocess: the count itself (a known kernel launch, copies each way)
and, on the 2D bench scene and a softening scene, each step taken as `geompm run` takes it (time step, step,
health and domain checks), that a step reads exactly one block of numbers from the device and sends nothing to it,
also where the particles are sorted on the device every step (the sort takes its cell ranges from the last step's
bounds and leaves the host's own arrays to be put in order when the host next reads them; before, a sort read its
ranges and sent its sizes: 6 blocking copies more a step).
Before (50c40d9): 19 and 17 copies to the host and 19 and 17 to the device per step (the health and domain
checks brought the whole particle state to the host, and the next step sent it back; each stage's accumulator
and each reduction was one more blocking copy).  Now one copy to the host (the step's tally,
backend/cuda_tally.py) and none to the device; five launches a step where the scenes sort nothing (G2P, the
particle rules, the law and the step-end row in one: decision 80).  Counts before and after for every bench scene:
benchmarks/results/2026-12-06-issue59/."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
pytest.importorskip("numba_cuda")
SIM = dict(os.environ, NUMBA_ENABLE_CUDASIM="1")

PROBE = """
import numpy as np
from numba import cuda
from geompm.bench.cuda_counts import counting

@cuda.jit(device=True)
def twice(x):
    return 2.0 * x

@cuda.jit
def double(a):
    i = cuda.grid(1)
    if i < a.shape[0]:
        a[i] = twice(a[i])

@cuda.jit
def scale(a, f):
    i = cuda.grid(1)
    if i < a.shape[0]:
        a[i] *= f

from geompm.bench.cuda_replay import compare
steps = [[], []]
with counting(launches=steps[0]) as c:
    d = cuda.to_device(np.arange(4.0))
    double[1, 4](d)
    double[1, 4](np.arange(4.0))
    out = d.copy_to_host()
    cuda.synchronize()
e = cuda.device_array(4)
with counting(launches=steps[1]):
    double[1, 4](d)
    double[1, 4](d)
    scale[1, 4](d, 0.5)
third = []  # the same three launches: another array in the second, another scalar in the third
with counting(launches=third):
    double[1, 4](d)
    double[1, 4](e)
    scale[1, 4](d, 0.25)
print({k: c[k] for k in ("launches", "implicit", "h2d", "d2h", "syncs", "blocking", "allocs")}, out.tolist())
print(compare(steps[1], third), compare(steps[0], steps[1]))
"""


def test_the_counter_sees_launches_copies_and_synchronisations():
    """Two launches (the device function inside is none), one numpy argument (an implicit round trip, whose copy
    back numba makes through the same call: two copies to the host), one explicit copy each way, one
    synchronisation; all four copies and the synchronisation but the implicit one's copy to the device (made
    inside the launch) make the host wait: four blocking; one device array made (the explicit copy's).
    The launches as a graph would see them (geompm/bench/cuda_replay.py): three launches against the same three
    with another device array in the second and another scalar in the third: one identical, one array, one
    scalar, the same kernels and grids; against a first block that handed a host array and launched one kernel
    fewer: one host array (never capturable), the third launch new (an array: another graph)."""
    r = subprocess.run([sys.executable, "-c", PROBE], env=SIM, capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    first, second = r.stdout.strip().splitlines()
    counts, out = first.rsplit(" [", 1)
    assert eval(counts) == {"launches": 2, "implicit": 1, "h2d": 1, "d2h": 2, "syncs": 1, "blocking": 4, "allocs": 1}
    assert out == "0.0, 2.0, 4.0, 6.0]"
    same, changed = second.split("} {")
    assert eval(same + "}") == {"identical": 1, "scalars": 1, "arrays": 1, "host": 0, "same_topology": 1}
    assert eval("{" + changed) == {"identical": 1, "scalars": 0, "arrays": 1, "host": 1, "same_topology": 0}


def test_an_ordinary_step_keeps_the_particles_on_the_device():
    """Also what a CUDA graph of a step would need (bench/cuda_replay.py, ``--replay``): no device array made in an
    ordinary step (a law's parameters changed by the strength trigger are copied into their array, the sort
    gathers into spares kept from sort to sort: backend/cuda_scratch.py), the same kernels on the same grids as
    the step before, and as arguments only the step's dt (or dt in place of the force's scale, f_scale) changed:
    in the grid update, P2G and the particle pass; where the particles are sorted every step, their arrays
    alternate with their spares, so the step equals the one two steps back in all but dt."""
    r = subprocess.run([sys.executable, "benchmarks/device/count_launches.py", "--steps", "3", "--replay", "dp2d",
                        "drucker_prager_softening_2d", "drucker_prager_cylinder_sorted"], env=SIM, capture_output=True,
                       text=True, cwd=ROOT, timeout=600)
    assert r.returncode == 0, r.stderr[-2000:]
    rows = {j["scene"]: j for j in (json.loads(line) for line in r.stdout.splitlines() if line.startswith("{"))}
    assert set(rows) == {"dp2d", "drucker_prager_softening_2d", "drucker_prager_cylinder_sorted"}
    for name, row in rows.items():
        # one blocking copy a step (the tally), nothing sent: no whole-state copy (18 arrays each way before)
        assert row["d2h"] == 1 and row["blocking"] == 1 and row["h2d"] == 0, (name, row)
        # the grid zeroed, P2G, the grid update with the walls' node rules (cuda_loops.UPDATE_GROUP), G2P with the
        # walls' particle rules, the law and the step-end row (cuda_loops.PARTICLE_STEP), the tally's reset: five
        # launches (eight before the particle pass was joined), and the sort's where it sorts
        assert row["implicit"] == 0, (name, row)
        assert row["launches"] == (5 if name != "drucker_prager_cylinder_sorted" else 23), (name, row)
        assert row["allocs"] == 0, (name, row)  # a new array each step before (the trigger's parameters, the sort)
        sorted_ = name == "drucker_prager_cylinder_sorted"
        same = row["replay"]["two_back" if sorted_ else "previous"]
        assert same["same_topology"] == 1 and same["arrays"] == 0 and same["host"] == 0, (name, row)
        assert same["scalars"] == (4 if sorted_ else 3), (name, row)  # dt: the update, P2G, the particle pass
        if sorted_:  # the obstacle's node group takes dt too; every sorted array and the sort's input alternate
            assert row["replay"]["previous"]["arrays"] >= 12, row


def test_the_particle_pass_apart_takes_three_launches_more():
    """solver.particle_pass "separate": G2P, the walls' particle rules and the law a kernel each, and the step-end
    reduction its own launch: 8 launches a step on dp2d instead of 5, still one blocking copy."""
    r = subprocess.run([sys.executable, "benchmarks/device/count_launches.py", "--steps", "2", "--cells", "4", "dp2d",
                        "--set", "solver.particle_pass=separate"], env=SIM, capture_output=True, text=True, cwd=ROOT,
                       timeout=600)
    assert r.returncode == 0, r.stderr[-2000:]
    row = next(json.loads(line) for line in r.stdout.splitlines() if line.startswith("{"))
    assert row["launches"] == 8 and row["blocking"] == 1 and row["h2d"] == 0, row


HOST_ALONE = """
import json, math, sys
from pathlib import Path
import numpy as np
sys.path.insert(0, "benchmarks/device")
from count_launches import bench_scenes
from geompm.api import scene_from_dict
from geompm.bench.cuda_host import host_only
from geompm.engine.runner import Runner
from geompm.engine.scheduler import Simulation

f, sets = bench_scenes(3)["dp2d"]
raw = json.loads(Path(f).read_text())
raw["solver"]["backend"] = "cuda"
sim = Simulation(scene_from_dict(raw, f.parent, sets))
sim.distribute()
be = sim.backend
x0 = be.host_state().p_x.copy()
dts, step = [], sim.step
sim.step = lambda dt: (dts.append(dt), step(dt))
seconds = host_only(sim, 20, repeats=2)
x1 = be.host_state().p_x.copy()
runner = Runner(sim, None, [], progress=False)
runner.start()
runner.advance(math.inf)
x2 = be.host_state().p_x.copy()
print(json.dumps({"seconds": seconds, "dts": dts, "moved_alone": float(np.abs(x1 - x0).max()),
                  "moved_after": float(np.abs(x2 - x1).max())}))
"""


def test_the_host_alone_takes_steps_without_the_device_and_gives_it_back():
    """geompm/bench/cuda_host.host_only (count_launches --host-steps): one real step, then steps whose launches
    return at once: the particles moved only in the real step (after it, every step the same path: the clock
    advances by the real step's dt each time), at least 20 + 2 x 20 steps taken, a positive time per step; and the
    launches and the tally's read are given back (the next step moves the particles again)."""
    r = subprocess.run([sys.executable, "-c", HOST_ALONE], env=SIM, capture_output=True, text=True, cwd=ROOT,
                       timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    out = json.loads(r.stdout.strip().splitlines()[-1])
    dts = out["dts"]
    assert out["seconds"] > 0.0 and len(dts) == 1 + 20 + 2 * 20 + 1, out  # real, untimed, two timed runs, real
    assert out["moved_alone"] > 0.0 and out["moved_after"] > 0.0, out  # the real first step, the given-back one
    alone = dts[1:-1]  # the same path every step: the time step from the real step's end values, exactly
    assert len(set(alone)) == 1 and alone[0] > 0.0, dts
