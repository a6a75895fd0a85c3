#!/usr/bin/env bash
# The scaling measurements of docs/parallel.md, in turn: 1 rank against 2 ranks (one numba thread each),
# three rounds in alternating order, for dp3d (204k particles), the main job as shipped (4800 particles)
# and at h = 0.025 m (38k); dp3d at 26k on 1 rank (the per-step fixed cost); the exchange costs.
#   bash benchmarks/parallel/measure.sh OUT_DIR
set -euo pipefail
out="$1"; mkdir -p "$out"
here="$(cd "$(dirname "$0")" && pwd)"; root="$(cd "$here/../.." && pwd)"
export NUMBA_NUM_THREADS=1
mpiexec="$(dirname "$(command -v python)")/mpiexec"
one() { python "$here/scaling.py" "$@"; }
two() { "$mpiexec" -n 2 python "$here/scaling.py" "$@"; }
scene() {  # label case steps [sets...]
  local label="$1" case="$2" steps="$3"; shift 3
  local sets=(); for s in "$@"; do sets+=(--set "$s"); done
  for round in 1 2 3; do
    if (( round % 2 )); then
      one "$case" "$out/${label}_r1_$round.json" --steps "$steps" "${sets[@]}"
      two "$case" "$out/${label}_r2_$round.json" --steps "$steps" "${sets[@]}"
    else
      two "$case" "$out/${label}_r2_$round.json" --steps "$steps" "${sets[@]}"
      one "$case" "$out/${label}_r1_$round.json" --steps "$steps" "${sets[@]}"
    fi
  done
}
scene dp3d "$root/benchmarks/dp3d.json" 60
scene mainjob "$root/cases/debris_obstacle.json" 150
scene mainjob_h025 "$root/cases/debris_obstacle.json" 80 grid.cell_size=0.025
for round in 1 2 3; do
  one "$root/benchmarks/dp3d.json" "$out/dp3d26k_r1_$round.json" --steps 150 --set grid.cell_size=0.03125
done
"$mpiexec" -n 2 python "$here/comm_costs.py" "$out/comm_costs.json"
"$mpiexec" -n 2 python "$here/comm_costs.py" "$out/comm_costs_swap_halo_dp3d128.json" --bytes 500000
lscpu | grep -E "Model name|^CPU\(s\)" > "$out/machine.txt"
