#!/usr/bin/env bash
# What rebalancing buys: the dam break (cases/dam_break.json) to t = 0.25 s on 3 ranks with the slabs
# rebalanced every 100 steps (the default) and never; status.json gives the particles per rank at the end.
#   bash benchmarks/parallel/rebalance.sh OUT_DIR
set -euo pipefail
out="$1"; mkdir -p "$out"
root="$(cd "$(dirname "$0")/../.." && pwd)"
mpiexec="$(dirname "$(command -v python)")/mpiexec"
export NUMBA_NUM_THREADS=1
for every in 100 0; do
  /usr/bin/time -f "%e s wall" "$mpiexec" -n 3 python -m geompm.cli run "$root/cases/dam_break.json" --quiet \
    --out "$out/dam_break_rebalance_$every" --set solver.rebalance_interval=$every --set outputs.1.interval=0.25 \
    2> "$out/dam_break_rebalance_$every.time"
  python -c "import json,sys; s=json.load(open('$out/dam_break_rebalance_$every/status.json')); print($every, s['steps'], s['wall_seconds'], s['mpi'])"
done
