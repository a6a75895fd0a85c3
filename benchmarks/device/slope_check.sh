#!/bin/sh
# The GPU check of the slope-stability work (issue 37), one command of under 7 minutes on a machine with an
# NVIDIA GPU and no network (run from the repository root, wheels carried as for run.sh):
#   sh benchmarks/device/slope_check.sh [OUTDIR]
# 1. the softening laws and the strength trigger, CPU against CUDA on the tiny scenes (3 steps);
# 2. cases/slope_failure.json, CPU against CUDA after 200 steps;
# 3. cases/slope_failure.json to its end on the GPU at h = 0.5, 0.25 and 0.125 m, each summarised by
#    benchmarks/device/slope_summary.py (failure time, front, deposit) and its series.csv kept;
# 4. the bench scenes fluid3d and dp3d at 1.6M particles, float64 and float32.
# Everything it prints is also written to OUTDIR/slope_gpu.log.
set -u
out=${1:-${OUT:-benchmarks/results}}
mkdir -p "$out"
log="$out/slope_gpu.log"
here=$(cd "$(dirname "$0")" && pwd)
{
  . "$here/common.sh"
  gpu_start 400 || exit 2
  step 100 python3 tests/cuda/cuda_parity.py --steps 3 mohr_coulomb_softening_trigger drucker_prager_softening_2d
  step 60 python3 tests/cuda/cuda_parity.py --steps 200 --case cases/slope_failure.json
  for h in 0.5 0.25 0.125; do
    t0=$(date +%s)
    step 150 geompm run cases/slope_failure.json --quiet --overwrite --out "/tmp/slope_failure_$h" \
      --set solver.backend=cuda --set grid.cell_size="$h"
    echo "h = $h m: $(( $(date +%s) - t0 )) s wall, compilation included"
    python3 "$here/slope_summary.py" "/tmp/slope_failure_$h"
    cp "/tmp/slope_failure_$h/series.csv" "$out/slope_failure_cuda_h$h.csv" 2>/dev/null
  done
  for p in float64 float32; do
    step 60 geompm bench --backend cuda --no-cold --no-bandwidth --json --steps 30 --set grid.cell_size=0.0078125 \
      --set solver.precision="$p" --scene fluid3d --scene dp3d
  done
  date -u
} 2>&1 | tee "$log"
