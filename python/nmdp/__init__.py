"""nmdp: legged robots on rigid and granular ground with learned contact models.

The compiled part is nmdp._core (pybind11); everything it offers is re-exported here. The
distributed sweeps are nmdp.sweep (Dask), imported on use.
"""
from ._core import *  # noqa: F401,F403
from ._core import __doc__  # noqa: F401
