# What the GPU scripts share (run.sh, slope_check.sh); sourced from the repository root, with $here set to this
# folder, inside the script's logged block.
#   gpu_start SECONDS   prints the date and the GPU, installs geompm (install.sh) and starts one deadline,
#                       BUDGET seconds (default SECONDS) from the end of the install; with DRY=1 it installs
#                       nothing and runs under numba-cuda's simulator (the scripts then shrink their sizes)
#   step LIMIT CMD ...  runs CMD with a timeout of LIMIT seconds or what is left of the deadline, whichever is
#                       less, names it if it is cut, fails or is skipped, and prints the seconds it took
gpu_start() {
  date -u
  if [ -n "${DRY:-}" ]; then  # the dry run: this environment's geompm under numba-cuda's simulator
    echo "dry run (DRY=1): numba-cuda's simulator, the scripts' own sizes replaced by tiny ones, no install"
    export NUMBA_ENABLE_CUDASIM=1
    budget_scale=4
  else
    nvidia-smi --query-gpu=name,memory.total,driver_version,clocks.max.sm --format=csv || echo "nvidia-smi failed"
    . "$here/install.sh" || return 2
    python3 -c "from numba import cuda; cuda.detect()"
  fi
  export PYTHONUNBUFFERED=1
  start=$(date +%s)
  budget=${BUDGET:-$(($1 * ${budget_scale:-1}))}
}

step() {
  limit=$1; shift
  [ -n "${DRY:-}" ] && limit=$((limit * 4))  # the simulator runs kernels in Python
  left=$((budget - $(date +%s) + start))
  if [ "$left" -le 5 ]; then echo "skipped, no time left: $*"; return; fi
  [ "$limit" -gt "$left" ] && limit=$left
  t0=$(date +%s)
  timeout "$limit" "$@" || echo "failed or cut at ${limit} s: $*"
  echo "[$(($(date +%s) - t0)) s: $*]"
}
