#!/bin/sh
# Fills benchmarks/device/wheels (git-ignored) with the wheels that benchmarks/device/install.sh installs on
# a GPU machine without network: geompm's dependencies (pyproject.toml) for CPython $PYVER (3.12, the H200
# machines' python3) on manylinux x86-64, less the packages that machine's image already holds (the list
# below, from .library/device/KINDS.md: numpy, numba, numba-cuda and the CUDA 13.0 toolkit among them).
#   sh benchmarks/device/fetch_wheels.sh [DEST]
# About 75 MB, rasterio 39 MB of it; the device tool carries at most 64 MiB with the working tree, so LEAN=1
# leaves rasterio out (36 MB: then terrain DEMs and GIS releases cannot be read there). Name the folder in the
# run's `carry` (["benchmarks/device/wheels"]).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
dest=${1:-$here/wheels}
py=${PYVER:-3.12}
image_has="attrs certifi click cloudpickle fsspec h5py jinja2 llvmlite markdown_it_py markupsafe mdurl msgpack
numba numpy packaging psutil pygments pyparsing pyyaml rich scipy sortedcontainers toolz tqdm typing_extensions
zipp"
deps=$(python3 -c "import tomllib, sys; print(' '.join(repr(d) for d in tomllib.load(open(sys.argv[1], 'rb'))['project']['dependencies']))" "$root/pyproject.toml")
tmp=$(mktemp -d)
# shellcheck disable=SC2086
eval python3 -m pip download -q --only-binary=:all: --python-version "$py" --implementation cp \
  --platform manylinux_2_28_x86_64 --platform manylinux_2_27_x86_64 --platform manylinux_2_17_x86_64 \
  --platform manylinux2014_x86_64 --platform manylinux1_x86_64 -d "$tmp" $deps
# The image's numpy 2.5 removed np.row_stack, which its numba-cuda 0.30.4 still overloads when it compiles a
# kernel (seen on the H200 machine, 2026-12-04): carry the numpy this machine's venv runs (2.4), 17 MB.
python3 -m pip download -q --only-binary=:all: --python-version "$py" --implementation cp \
  --platform manylinux_2_28_x86_64 --platform manylinux_2_17_x86_64 --platform manylinux2014_x86_64 \
  --no-deps -d "$tmp/numpy" "numpy>=2.0,<2.5"
mkdir -p "$dest"
cp "$tmp"/numpy/*.whl "$dest/"
for whl in "$tmp"/*.whl; do
  name=$(basename "$whl" | sed 's/-.*//' | tr 'A-Z-' 'a-z_')
  case " $(echo $image_has) " in
    *" $name "*) ;;
    *) [ "${LEAN:-0}" = 1 ] && [ "$name" = rasterio ] || cp "$whl" "$dest/" ;;
  esac
done
ls "$dest"
du -sh "$dest"
