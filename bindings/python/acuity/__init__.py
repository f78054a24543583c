"""acuity: draw only the geometric detail a viewer can see.

Top level: Profile, Scheduler, SchedulerConfig, Eye, Gaze, Frame (the runtime); FileError (a
ValueError): a file that cannot be read or written as asked (missing, not a regular file, too large,
outside its folder, a refused output).
Submodules:
    acuity.models   vision models: thresholds, CSFs, cutoffs, Guenter's layers (numpy-vectorised)
    acuity.spectra  snapshots, lost-contrast analysis, Reddy features, profiling, profile files
    acuity.lodgen   chains of levels of detail (decimation, Hausdorff error, glTF with MSFT_lod)
    acuity.clusters detail that follows the gaze inside one object: cluster cuts (load, select)
    acuity.sim      simulated runs of a scene through the LOD rules (as acuity simulate / explain)
    acuity.foveation  per-tile shading-rate and mip-bias maps and Guenter layers for one eye
    acuity.bake     (import acuity.bake) bake an asset library (chains, profiles, index) through the cache, locally or on Dask

Use from a build tree with ``PYTHONPATH=<build>/python /usr/bin/python3`` (Debian's python3), or
install it: ``pip install --no-index --no-build-isolation <build>/python`` (e.g. into a venv made
with ``/usr/bin/python3 -m venv --system-site-packages``).
"""
import sys as _sys

from . import _acuity

__version__ = _acuity.__version__
models = _acuity.models
spectra = _acuity.spectra
lodgen = _acuity.lodgen
foveation = _acuity.foveation
sim = _acuity.sim
clusters = _acuity.clusters
for _name in ("models", "spectra", "lodgen", "foveation", "sim", "clusters"):
    _sys.modules[__name__ + "." + _name] = getattr(_acuity, _name)

from ._acuity import (Eye, Evaluation, FileError, Frame, Gaze, Profile, ProfileTables, Scheduler, SchedulerConfig, SelectionRule,  # noqa: E402
                      View, ViewBlend, ViewProjection, ViewRule, FLAG_BUDGET_FORCED, FLAG_CHANGED, FLAG_EYE_INSIDE, FLAG_HELD,
                      FLAG_INVALID_INPUT, FLAG_NO_GAZE)

__all__ = ["models", "spectra", "lodgen", "foveation", "sim", "clusters", "Eye", "FileError", "Frame", "Gaze", "Profile", "ProfileTables", "Scheduler", "SchedulerConfig",
           "SelectionRule", "View", "ViewBlend", "ViewProjection", "ViewRule", "Evaluation", "__version__"]
