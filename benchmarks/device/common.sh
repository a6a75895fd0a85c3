# What the GPU scripts share (run.sh, slope_check.sh); sourced from the repository root, with $here set to this
# folder, inside the script's logged block.
#   gpu_start SECONDS   prints the date and the GPU, installs geompm (install.sh) and starts one deadline,
#                       BUDGET seconds (default SECONDS) from the end of the install
#   step LIMIT CMD ...  runs CMD with a timeout of LIMIT seconds or what is left of the deadline, whichever is
#                       less, and names it if it is cut, fails or is skipped
gpu_start() {
  date -u
  nvidia-smi --query-gpu=name,memory.total,driver_version,clocks.max.sm --format=csv || echo "nvidia-smi failed"
  . "$here/install.sh" || return 2
  python3 -c "from numba import cuda; cuda.detect()"
  export PYTHONUNBUFFERED=1
  start=$(date +%s)
  budget=${BUDGET:-$1}
}

step() {
  limit=$1; shift
  left=$((budget - $(date +%s) + start))
  if [ "$left" -le 5 ]; then echo "skipped, no time left: $*"; return; fi
  [ "$limit" -gt "$left" ] && limit=$left
  timeout "$limit" "$@" || echo "failed or cut at ${limit} s: $*"
}
