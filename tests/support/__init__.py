"""Helpers the tests share, none of them a test: the cases and paths (cases.py), the dimension-generic
reference transfer and the kernels under test, a DEM writer, the elastic bar's run, a fake plugin
distribution, the import graph and its declared layers, the mesh fuzzer."""
