#!/bin/sh
# The GPU check of issue 21, for one machine with an NVIDIA GPU and no network (run from the repository root):
#   sh benchmarks/device/run.sh [OUTDIR]
# Installs geompm with benchmarks/device/install.sh: the machine's python3 gives numpy, numba, numba-cuda and
# CUDA, the wheels in benchmarks/device/wheels the rest (not committed: fill the folder on a machine with
# network with `sh benchmarks/device/fetch_wheels.sh`, about 47 MB, and carry it: the device tool's
# `carry: ["benchmarks/device/wheels"]`).  Then it prints the GPU,
# benchmarks fluid3d and dp3d on the cuda backend at 64, 128 and 256 cells per side (204k, 1.6M, 13M
# particles), float32 and float64 (solver.precision), the tiled P2G at 128 and 256 (solver.p2g), checks CPU against CUDA on the tiny scenes (the device
# sort, a checkpoint across backends, two float32 scenes) and on cases/dam_break.json after 200 steps, and
# ends in under 8 minutes (every command has its own timeout).  Everything it prints is also written to OUTDIR/gpu_check.log.
set -u
out=${1:-${OUT:-benchmarks/results}}
mkdir -p "$out"
log="$out/gpu_check.log"
here=$(cd "$(dirname "$0")" && pwd)
{
  date -u
  nvidia-smi --query-gpu=name,memory.total,driver_version,clocks.max.sm --format=csv || echo "nvidia-smi failed"
  . "$here/install.sh" || exit 2
  python3 -c "from numba import cuda; cuda.detect()"
  export PYTHONUNBUFFERED=1
  for n in 64 128 256; do
    h=$(python3 -c "print(1/$n)")
    steps=$([ $n = 256 ] && echo 20 || echo 50)
    for p in float32 float64; do
      timeout 40 geompm bench --backend cuda --scene fluid3d --scene dp3d --no-cold --no-bandwidth --steps $steps \
        --json --set grid.cell_size=$h --set solver.precision=$p || echo "bench at $n cells per side, $p, failed or timed out"
    done
  done
  for n in 128 256; do  # the tiled P2G (solver.p2g), float32
    h=$(python3 -c "print(1/$n)")
    timeout 40 geompm bench --backend cuda --scene fluid3d --scene dp3d --no-cold --no-bandwidth --steps 20 \
      --json --set grid.cell_size=$h --set solver.precision=float32 --set solver.p2g=tiled || echo "tiled bench at $n failed"
  done
  # the issue's equality check first; the tiny scenes (every law and stage) with what time is left: on a
  # fresh machine both sides compile cold
  timeout 70 python3 tests/cuda_parity.py --steps 200 --case cases/dam_break.json || echo "dam-break parity failed"
  timeout 60 python3 tests/cuda_parity.py --steps 3 || echo "tiny-scene parity failed or timed out"
  date -u
} 2>&1 | tee "$log"
