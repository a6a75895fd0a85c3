"""Verification harnesses that the tests and the benchmarks share: the scenes, closed forms and runners of
geompm's verification cases (a loaded column, saturated columns, slopes, the numerical envelope, the hockey
stick, a block on a DEM incline, the scenes run over MPI ranks).  The benchmarks stand on these, never on
tests/; a harness that replays a shipped case reads it from the clone's cases/ folder (``cases.CASES``)."""
