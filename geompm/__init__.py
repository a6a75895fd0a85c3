"""geompm: an explicit Material Point Method framework for geotechnical hazards.

SI units throughout: metres, seconds, kilograms, pascals.  The packages, lowest layer first
(docs/architecture.md; tests/repository/test_layers.py holds the order and checks it):

- ``errors``, ``version``: what every layer may use;
- ``contract``: the plugin and stage bases, parameter layouts, the entry-point registry;
- ``kernels``: numba functions of particles and nodes (shape functions, transfers, reductions);
- ``mpm``: the particle state, the grid window, memory sizing;
- ``files``: atomic writes, file ownership, DEM and surface-mesh readers;
- ``materials``, ``damping``, ``contact``: laws and contact rules;
- ``boundaries``, ``obstacles``: boundary and obstacle plugins;
- ``backend``: owns every loop, the wave speeds and the stable step;
- ``writers``: output writer plugins;
- ``schema``: the case format and its validation;
- ``setup``: a validated case made into a Scene (bodies, release areas, geostatic stress);
- ``engine``: the time loop, health checks, checkpoints;
- ``api``, ``study``, ``stability``, ``bench``, ``plots``, ``testing``: what users and plugin authors call;
- ``cli``: the ``geompm`` command.
"""

from geompm.version import __version__

__all__ = ["Run", "__version__", "run", "stability"]


def __getattr__(name: str):
    """``geompm.run`` and ``geompm.Run`` (geompm/api.py) and ``geompm.stability`` (the factor of safety,
    stability/search_run.py), imported on first use so that ``import geompm`` stays light (numba and the laws
    load only when a case runs)."""
    if name in ("run", "Run"):
        from geompm import api

        return getattr(api, name)
    if name == "stability":
        import geompm.stability

        return geompm.stability
    raise AttributeError(f"module 'geompm' has no attribute {name!r}")
