"""dashpot: contact laws for granular collisions, chosen by name at run time.

The laws are plugins (shared libraries): those built into the package (its ``plugins``
directory), and any found in the directories of ``DASHPOT_PLUGIN_PATH`` (searched first:
``target/release`` of a dashpot checkout); ``load_plugin(path)`` adds one more file, a
third-party law say. SI units throughout: overlaps in m, rates in m/s (positive approaching),
masses in kg, radii in m, forces in N, moduli in Pa, times in s.

    >>> import numpy as np, dashpot
    >>> hsd = dashpot.ContactLaw("hsd", eps=0.3)
    >>> b = hsd.bind(young=6e9, poisson=0.3)
    >>> f = b.force(np.array([1e-5]), np.array([0.1]), np.array([1e-3]), np.array([5e-3]))
    >>> c = dashpot.collide("hsd", v0=1.0, eps=0.54)
    >>> round(c["restitution"], 6)
    0.54

What the CLI computes, the package computes to the bit: ``collide``, ``sweep``, ``calibrate``,
``bed`` (as ``dashpot bed --json``) and DEM scenes (``Scene``, as ``dashpot dem --scene FILE
--json``). Long runs release the GIL, and Ctrl-C stops them with ``KeyboardInterrupt``.

Every refusal is an exception naming the value: ``ValueError`` for a bad name or value,
``dashpot.PluginError`` for a plugin that cannot be loaded, ``RuntimeError`` for a law or a
run that failed (a panic in a plugin, a non-finite force, a particle lost).
"""

from __future__ import annotations

import os as _os
from typing import List

from . import _dashpot
from ._dashpot import PluginError
from ._laws import (BoundContactLaw, BoundHeatLaw, BoundRollingLaw, BoundTangentialLaw, BoundTwistingLaw,
                    ContactLaw, HeatLaw, RestitutionLaw, RollingLaw, TangentialLaw, TwistingLaw, laws,
                    load_plugin)
from ._runs import bed, calibrate, collide, sweep
from ._scene import Scene

__all__ = [
    "PluginError",
    "laws",
    "load_plugin",
    "ContactLaw",
    "BoundContactLaw",
    "TangentialLaw",
    "BoundTangentialLaw",
    "RollingLaw",
    "BoundRollingLaw",
    "TwistingLaw",
    "BoundTwistingLaw",
    "HeatLaw",
    "BoundHeatLaw",
    "RestitutionLaw",
    "collide",
    "sweep",
    "calibrate",
    "bed",
    "Scene",
]

__version__ = "0.4.0"


def _plugin_dirs() -> List[str]:
    """The package's own plugin directory, if it has one (searched after DASHPOT_PLUGIN_PATH)."""
    d = _os.path.join(_os.path.dirname(__file__), "plugins")
    return [d] if _os.path.isdir(d) else []


