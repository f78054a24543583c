"""acuity: draw only the geometric detail a viewer can see.

Submodules:
    acuity.models  vision models: thresholds, CSFs, cutoffs, Guenter's layers (numpy-vectorised)

Use from a build tree with ``PYTHONPATH=<build>/python /usr/bin/python3`` (Debian's python3).
"""
import sys as _sys

from . import _acuity

__version__ = _acuity.__version__
models = _acuity.models
_sys.modules[__name__ + ".models"] = models

__all__ = ["models", "__version__"]
