#!/bin/sh
# Granular column collapse (DP, phi = 31 deg) against Lube et al. (2005): L0 = 0.1 m, aspect a = H0/L0,
# grids H0/20, H0/40, H0/80 (GRIDS="20 40 80 160": others), FLIP with tau = sqrt(H0/g) (TAU=k: k sqrt(H0/g)),
# deposit front and height at 0.05 H0 (issue 15). One geompm study per aspect ratio; each prints its runs
# and the observed order of convergence; the command of each is echoed first.  The back wall x = 0 takes
# Coulomb friction WALL_MU (e.g. 0.6009 = tan 31 deg, as the floor; default slip: the case's slip wall).
#   sh benchmarks/convergence/lube_study.sh OUTDIR [a ...]   (default a = 0.5 1 2 3 5; RESUME=--resume to go on)
out=${1:-studies/lube}; shift
mu=${WALL_MU:-slip}
wall="--set boundaries.0.condition=friction --set boundaries.0.friction=$mu"
[ "$mu" = slip ] && wall=""
for a in ${*:-0.5 1 2 3 5}; do
  set -- $(python3 -c "
a=$a; L0=0.1; H0=a*L0; g=9.81
lube=1.2*a if a<2.3 else 1.9*a**(2/3)
print(H0, round(L0*(1.5+2*lube), 4), round(1.2*H0, 4), ','.join(f'{H0/n:.6g}' for n in map(int, '${GRIDS:-20 40 80}'.split())),
      round(0.05*H0, 6), round(${TAU:-1}*(H0/g)**0.5, 4))")
  cmd="geompm study cases/column_collapse.json --out $out/a$a ${RESUME:---overwrite} --workers 1 \
--set bodies.0.geometry.max=[0.1,$1] --set grid.extent=[$2,$3] --set time.end=1.0 \
--set 'outputs=[{\"writer\":\"series\",\"interval\":0.01,\"deposit_threshold\":$5}]' \
--set solver.flip_relaxation_time=$6 $wall --vary grid.cell_size=$4 --metric runout --metric height"
  echo "$cmd"
  eval "$cmd"
done
