#!/bin/sh
# Installs geompm and the mu_i plugin on a GPU machine without network, into SITE (default
# /tmp/geompm-site), with no dependency resolution: the image's python3 gives numpy, numba, numba-cuda,
# scipy, h5py and CUDA; benchmarks/device/wheels (fetch_wheels.sh) gives the rest.  Source it from the
# repository root, so that PYTHONPATH and PATH stay set:  . benchmarks/device/install.sh
site=${SITE:-/tmp/geompm-site}
wheels=$(pwd)/benchmarks/device/wheels
if ! ls "$wheels"/*.whl >/dev/null 2>&1; then
  echo "no wheels in $wheels: run benchmarks/device/fetch_wheels.sh on a machine with network and carry the folder"
  return 2 2>/dev/null || exit 2
fi
# one pip call: a second --target install into the same folder skips its existing bin/ (the geompm script)
python3 -m pip install -q --no-index --no-deps --no-compile --no-build-isolation --upgrade --target "$site" \
  "$wheels"/*.whl . plugins/geompm-mu-i &&
  export PYTHONPATH="$site${PYTHONPATH:+:$PYTHONPATH}" PATH="$site/bin:$PATH" ||
  { echo "install from wheels failed"; return 2 2>/dev/null || exit 2; }
python3 -c "import geompm, numba, numba_cuda; print('geompm from', geompm.__file__, '| numba', numba.__version__, '| numba-cuda', numba_cuda.__version__)"
