"""One run over several processes (MPI): slabs of cells, halo sums, particle migration (docs/parallel.md)."""
