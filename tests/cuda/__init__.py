"""The CUDA backend without a GPU: numba-cuda's simulator against the CPU (cuda_parity.py) and every kernel
compiled to PTX for an H200 (cuda_compile.py); both scripts also run on a GPU machine
(benchmarks/device/run.sh)."""
