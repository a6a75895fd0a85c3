"""The factor of safety by strength reduction: trials of a case with its strength divided by F, on Dask.

The package is callable: ``geompm.stability(case, ...)`` is search_run.stability, which returns the JSON
object of `geompm stability --json`."""

import sys
import types


class _Callable(types.ModuleType):
    def __call__(self, case, **options):
        from geompm.stability.search_run import stability

        return stability(case, **options)


sys.modules[__name__].__class__ = _Callable
