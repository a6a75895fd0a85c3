"""Studies: many runs of one case (refinement, options, Monte Carlo draws) on Dask, and what they measure."""
