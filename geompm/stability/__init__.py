"""The factor of safety by strength reduction: trials of a case with its strength divided by F, on Dask."""
