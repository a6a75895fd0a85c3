#!/bin/sh
# CPU against CUDA on every shipped case family after STEPS steps (issue 21, point 3), one JSON line per case
# from tests/cuda/cuda_parity.py (largest relative difference of positions, velocities, stresses, densities and of
# every series column, particles matched by id).  On a machine without a GPU run it under numba-cuda's
# simulator, at the coarse grids below (the simulator runs each CUDA thread as Python):
#   NUMBA_ENABLE_CUDASIM=1 sh benchmarks/device/shipped_parity.sh [STEPS] > shipped_parity.jsonl
# On a GPU, SETS="" runs the cases at their own grids.
steps=${1:-200}
run() {
  case_file=$1; shift
  sets=""
  for kv in "$@"; do sets="$sets --set $kv"; done
  # shellcheck disable=SC2086
  python3 tests/cuda/cuda_parity.py --steps "$steps" --case "$case_file" ${SETS-$sets} || echo "{\"case\": \"$case_file\", \"failed\": true}"
}
run cases/elastic_bar.json grid.cell_size=1.0
run cases/dam_break.json grid.cell_size=0.02
run cases/column_collapse.json grid.cell_size=0.025
run cases/column_collapse_cross.json grid.cell_size=0.025
run cases/landslide.json grid.cell_size=0.5
run cases/inclined_flow.json grid.cell_size=0.04
run cases/debris_obstacle.json grid.cell_size=0.15
run cases/terrain_debris_flow.json grid.cell_size=2.5
run benchmarks/device/periodic_film.json grid.cell_size=0.02
