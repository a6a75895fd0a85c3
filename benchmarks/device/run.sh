#!/bin/sh
# The GPU check of issue 21, for one machine with an NVIDIA GPU and no network (run from the repository root):
#   sh benchmarks/device/run.sh [OUTDIR]
# Installs geompm with benchmarks/device/install.sh: the machine's python3 gives numpy, numba, numba-cuda and
# CUDA, the wheels in benchmarks/device/wheels the rest (not committed: fill the folder on a machine with
# network with `LEAN=1 sh benchmarks/device/fetch_wheels.sh`, about 37 MB (rasterio left out: the terrain scenes are then skipped), and carry it: the device tool's
# `carry: ["benchmarks/device/wheels"]`).  Then it prints the GPU,
# benchmarks fluid3d and dp3d on the cuda backend at 64, 128 and 256 cells per side (204k, 1.6M, 13M
# particles), float32 and float64 (solver.precision), with held steps at 128 (solver.held_step), the tiled P2G at
# 128 and 256 (solver.p2g), benchmarks saturated3d
# (saturated soil) at 64, checks CPU against CUDA on cases/dam_break.json and the saturated scene after 200 steps and on the tiny scenes (every law and stage, the device
# sort, a checkpoint across backends, two float32 scenes), and ends in under 8 minutes (one deadline, below).  Everything it prints is also written to OUTDIR/gpu_check.log.
set -u
out=${1:-${OUT:-benchmarks/results}}
mkdir -p "$out"
log="$out/gpu_check.log"
here=$(cd "$(dirname "$0")" && pwd)
{
  . "$here/common.sh"
  # One deadline for everything after the install (BUDGET seconds, default 430: the whole script within 8
  # minutes).  The measurements run in the order of what the issue's targets need: 13M particles first
  # (each scene and precision its own command: assembling 13M particles takes about 10-20 s before the first
  # step), then 1.6M, the dam-break equality check, 204k, the tiled P2G; every command gets its own
  # timeout or what is left, whichever is less, and is named if it is cut or skipped.
  gpu_start 430 || exit 2
  # DRY=1 (the dry run under the simulator): every command as below at DRY_CELLS cells per side (default 8:
  # 4-6 minutes on 2 cores, benchmarks/results/2026-12-06-issue59/device-dry-run.log; CI runs it at 3, about
  # 60 s alone: tests/cuda/test_device_script.py), one timed step, one parity step on a coarse dam break, one tiny
  # parity scene, each limit and the deadline four times longer
  steps200=200; dam=""; tiny=""; held=20
  [ -n "${DRY:-}" ] && { steps200=1; dam="--set grid.cell_size=0.05"; tiny="elastic_apic_quadratic_usl"; held=2; }
  bench() {  # timeout, cells per side, precision, timed steps, then scenes and extra options
    limit=$1; n=$2; p=$3; steps=$4; shift 4
    [ -n "${DRY:-}" ] && { n=${DRY_CELLS:-8}; steps=1; }
    step "$limit" geompm bench --backend cuda --no-cold --no-bandwidth --json --steps "$steps" \
      --set grid.cell_size="$(python3 -c "print(1/$n)")" --set solver.precision="$p" "$@"
  }
  for p in float32 float64; do
    bench 70 256 $p 10 --scene fluid3d
    bench 80 256 $p 10 --scene dp3d
  done
  # (the dry run runs each command once: at its tiny size a 128- or 64-cell command repeats a 256-cell one)
  [ -z "${DRY:-}" ] && for p in float32 float64; do bench 50 128 $p 30 --scene fluid3d --scene dp3d; done
  # the held step (solver.held_step, engine/held_step.py): the host reads the device once a batch of up to 20 steps
  bench 50 128 float32 40 --scene fluid3d --scene dp3d --set "solver.held_step={\"steps\": $held}"
  step 70 python3 tests/cuda/cuda_parity.py --steps "$steps200" --case cases/dam_break.json $dam
  [ -z "${DRY:-}" ] && for p in float32 float64; do bench 35 64 $p 50 --scene fluid3d --scene dp3d; done
  bench 60 256 float32 10 --scene fluid3d --set solver.p2g=tiled
  bench 60 128 float32 30 --scene dp3d --set solver.p2g=tiled
  # G2P, the particle stages and the law as three kernels (solver.particle_pass): against the 128-cell rows above
  bench 50 128 float32 30 --scene fluid3d --scene dp3d --set solver.particle_pass=separate
  # saturated soil (schemes/saturated/cuda.py): the bench scene and its CPU parity after 200 steps
  bench 60 64 float64 30 --scene saturated3d --scene dp3d
  step 60 python3 tests/cuda/cuda_parity.py --steps "$steps200" saturated_drucker_prager
  # what each step asks of the host (launches, copies, synchronisations) and its wall time on the device
  # (--replay: whether a step launches the previous step's kernels with the same device pointers, a CUDA graph's
  # condition, on the device's own arrays: bench/cuda_replay.py)
  if [ -n "${DRY:-}" ]; then step 60 python3 benchmarks/device/count_launches.py --steps 1 --cells 4 dp2d
    step 60 python3 benchmarks/device/count_launches.py --steps 2 --held 2 --cells 4 dp2d
    step 60 python3 benchmarks/device/count_launches.py --steps 3 --cells 3 --replay dp2d
  else step 60 python3 benchmarks/device/count_launches.py --steps 20 --cells 16
    step 60 python3 benchmarks/device/count_launches.py --steps 40 --cells 16 --held 20 fluid3d dp3d dp2d
    step 40 python3 benchmarks/device/count_launches.py --steps 4 --cells 16 --replay dp3d drucker_prager_cylinder_sorted
  fi
  # every law and stage on the GPU against the CPU, with what is left (both sides compile cold here)
  step 120 python3 tests/cuda/cuda_parity.py --steps 3 $tiny
  date -u
} 2>&1 | tee "$log"
