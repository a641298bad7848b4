"""dashpot: contact laws for granular collisions, chosen by name at run time.

The laws are plugins (shared libraries) found in the directories of ``DASHPOT_PLUGIN_PATH``
(``target/release`` after ``cargo build --release`` in a dashpot checkout) and in the
package's own ``plugins`` directory; ``load_plugin(path)`` adds one more file. SI units
throughout: overlaps in m, rates in m/s (positive approaching), masses in kg, radii in m,
forces in N, moduli in Pa.

    >>> import numpy as np, dashpot
    >>> hsd = dashpot.ContactLaw("hsd", eps=0.3)
    >>> b = hsd.bind(young=6e9, poisson=0.3)
    >>> f = b.force(np.array([1e-5]), np.array([0.1]), np.array([1e-3]), np.array([5e-3]))
    >>> c = dashpot.collide("hsd", v0=1.0, eps=0.54)
    >>> round(c["restitution"], 6)
    0.54

Every refusal is an exception naming the value: ``ValueError`` for a bad name or value,
``dashpot.PluginError`` for a plugin that cannot be loaded, ``RuntimeError`` for a law that
failed (a panic, a non-finite force).
"""

from __future__ import annotations

import json as _json
import os as _os
from typing import Any, Dict, List, Optional

import numpy as _np

from . import _dashpot
from ._dashpot import PluginError

__all__ = [
    "PluginError",
    "laws",
    "load_plugin",
    "ContactLaw",
    "BoundContactLaw",
    "TangentialLaw",
    "BoundTangentialLaw",
    "RestitutionLaw",
    "collide",
    "calibrate",
]


def _plugin_dirs() -> List[str]:
    """The package's own plugin directory, if it has one (searched after DASHPOT_PLUGIN_PATH)."""
    d = _os.path.join(_os.path.dirname(__file__), "plugins")
    return [d] if _os.path.isdir(d) else []


def laws() -> List[Dict[str, Any]]:
    """Every law found: dicts with name, kind, summary, doc, plugin, params (each with name,
    unit, default and valid range), as ``dashpot laws --json`` lists them."""
    return _json.loads(_dashpot.laws())


def load_plugin(path: str) -> None:
    """Loads the plugin library at ``path``; its laws join those already found.

    Raises ``PluginError`` if the file is not a dashpot plugin of a compatible sdk."""
    _dashpot.load_plugin(_os.fspath(path))


def _f64(name: str, x: Any, n: Optional[int] = None) -> _np.ndarray:
    """``x`` as a contiguous float64 array (no copy when it already is one)."""
    try:
        a = _np.ascontiguousarray(x, dtype=_np.float64)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{name}: cannot be read as float64 numbers ({e})") from None
    if a.ndim == 0:
        a = a.reshape(1)
    if a.ndim != 1:
        raise ValueError(f"{name} has shape {a.shape}: it must be one-dimensional, one value per contact")
    if n is not None and a.shape[0] != n:
        raise ValueError(f"{name} has {a.shape[0]} values, delta {n}: one value per contact")
    return a


class BoundContactLaw:
    """A contact law bound to a pair of materials (see ``ContactLaw.bind``)."""

    def __init__(self, inner: Any) -> None:
        self._inner = inner

    @property
    def name(self) -> str:
        """The law's name."""
        return self._inner.name

    @property
    def history_slots(self) -> int:
        """History values the law keeps per contact (0 for a memoryless law)."""
        return self._inner.history_slots

    def force(self, delta, rate, mass, radius, history=None, out=None) -> _np.ndarray:
        """Normal forces (N, > 0 repulsive) of N contacts: overlaps ``delta`` (m), rates
        ``rate`` (m/s, > 0 approaching), effective masses ``mass`` (kg) and radii ``radius``
        (m), each an array of N values (float64 arrays are used without a copy). A law with
        history needs ``history``, a float64 array of shape (N, history_slots), zeros at first
        touch, which it updates in place. ``out``, a float64 array of N values, receives the
        forces instead of a new array (a loop over steps then allocates nothing)."""
        d = _f64("delta", delta)
        n = d.shape[0]
        args = [d, _f64("rate", rate, n), _f64("mass", mass, n), _f64("radius", radius, n)]
        if out is not None and not (isinstance(out, _np.ndarray) and out.dtype == _np.float64
                                    and out.ndim == 1 and out.flags.c_contiguous and out.flags.writeable):
            raise ValueError("out must be a writeable, contiguous one-dimensional float64 numpy array")
        if history is None:
            return self._inner.force(*args, None, out)
        if not (isinstance(history, _np.ndarray) and history.dtype == _np.float64 and history.flags.c_contiguous):
            raise ValueError("history must be a C-contiguous float64 numpy array of shape (N, history_slots), updated in place")
        return self._inner.force(*args, history.reshape(-1), out)


class ContactLaw:
    """Contact law ``name`` (see ``laws()``) with its parameters as keywords, checked by the
    law: ``ContactLaw("hsd", eps=0.3)``."""

    def __init__(self, name: str, **params: float) -> None:
        self.name = name
        self.params = dict(params)

    def bind(self, young: float, poisson: float, young2: Optional[float] = None,
             poisson2: Optional[float] = None, wall: bool = False) -> BoundContactLaw:
        """The law for a pair of materials: Young's modulus ``young`` (Pa) and Poisson's ratio
        ``poisson`` of the first body; the second another sphere (``young2``, ``poisson2``,
        default the first's) or, with ``wall=True``, a rigid wall."""
        return BoundContactLaw(_dashpot.bind_contact(self.name, self.params, young, poisson,
                                                     young2, poisson2, wall))

    def provenance(self) -> Dict[str, Any]:
        """The law's plugin file, versions and every parameter, as the CLI's JSON gives them."""
        return _json.loads(_dashpot.provenance(self.name, **self.params))


def _vectors(name: str, x: Any, n: int) -> _np.ndarray:
    """``x`` as a contiguous float64 array of shape (n, 3), flattened."""
    a = _np.ascontiguousarray(x, dtype=_np.float64)
    if a.shape != (n, 3):
        raise ValueError(f"{name} has shape {a.shape}: it must be ({n}, 3), one vector per contact")
    return a.reshape(-1)


class BoundTangentialLaw:
    """A tangential (friction) law bound to a pair of materials (see ``TangentialLaw.bind``)."""

    def __init__(self, inner: Any) -> None:
        self._inner = inner

    @property
    def history_slots(self) -> int:
        """History values per contact (3 for a tangential spring)."""
        return self._inner.history_slots

    def force(self, dt, normal, velocity, normal_force, delta, mass, radius, history) -> _np.ndarray:
        """Tangential forces (N), shape (N, 3), on N contacts over a step ``dt`` (s): unit
        normals ``normal`` (N, 3) from the partner to the particle, contact-point relative
        velocities ``velocity`` (N, 3, m/s), normal forces (N), overlaps (m), effective masses
        (kg) and radii (m); ``history``, a float64 array of shape (N, history_slots), zeros at
        first touch, is advanced in place."""
        fn = _f64("normal_force", normal_force)
        n = fn.shape[0]
        if not (isinstance(history, _np.ndarray) and history.dtype == _np.float64 and history.flags.c_contiguous):
            raise ValueError("history must be a C-contiguous float64 numpy array of shape (N, history_slots), updated in place")
        f = self._inner.force(float(dt), _vectors("normal", normal, n), _vectors("velocity", velocity, n), fn,
                              _f64("delta", delta, n), _f64("mass", mass, n), _f64("radius", radius, n),
                              history.reshape(-1))
        return f.reshape(n, 3)


class TangentialLaw:
    """Tangential law ``name`` (e.g. ``"mindlin"``) with its parameters as keywords."""

    def __init__(self, name: str, **params: float) -> None:
        self.name = name
        self.params = dict(params)

    def bind(self, young: float, poisson: float, young2: Optional[float] = None,
             poisson2: Optional[float] = None, wall: bool = False) -> BoundTangentialLaw:
        """The law for a pair of materials, as ``ContactLaw.bind``."""
        return BoundTangentialLaw(_dashpot.bind_tangential(self.name, self.params, young, poisson,
                                                           young2, poisson2, wall))


class RestitutionLaw:
    """Restitution law ``name`` (e.g. ``"mcnamara-falcon"``) with its parameters as keywords,
    for a particle (``diameter`` m, ``density`` kg/m³, ``young`` Pa, ``poisson``; defaults:
    the MCC granule) against an identical one or a ``wall``."""

    def __init__(self, name: str, *, diameter: float = 0.01, density: float = 1500.0,
                 young: float = 6e9, poisson: float = 0.3, wall: bool = False, **params: float) -> None:
        self.name = name
        self.params = dict(params)
        self._pair = (diameter, density, young, poisson, wall)

    def r(self, speeds) -> _np.ndarray:
        """The coefficient of restitution at each normal impact speed (m/s)."""
        return _dashpot.restitution(self.name, self.params, _f64("speeds", speeds), *self._pair)


def collide(law: str, v0: float = 1.0, *, diameter: float = 0.01, density: float = 1500.0,
            young: float = 6e9, poisson: float = 0.3, wall: bool = False,
            end: Optional[str] = None, rtol: float = 1e-11, record: bool = False,
            **params: float) -> Dict[str, Any]:
    """One head-on collision, as ``dashpot collide --json`` computes it: ``law`` with its
    parameters as keywords, a sphere (``diameter`` m, ``density`` kg/m³, ``young`` Pa,
    ``poisson``; defaults: Antypov & Elliott's MCC granule) against an identical sphere or a
    ``wall``, impact speed ``v0`` (m/s); ``end`` is ``"overlap"`` (default) or ``"force"``.

    Returns a dict: restitution, contact_time (s), max_overlap (m), max_overlap_time (s),
    stuck (adhesive laws), tensile_peak (N), steps, force_evals, pair, params, provenance;
    with ``record=True`` also the trajectory as arrays ``t``, ``delta``, ``rate``, ``force``.
    The GIL is released while it runs."""
    out = _dashpot.collide(law, params, float(v0), diameter, density, young, poisson, wall, end,
                           rtol, record)
    out["params"], out["provenance"] = _provenance(law, params)
    return out


_PROVENANCE: Dict[str, Any] = {}


def _provenance(law: str, params: Dict[str, float]):
    """(params, provenance) of a law as the CLI's JSON gives them, computed once per law and
    parameters (the dicts are shared between results: copy them before changing them)."""
    key = law + repr(sorted(params.items()))
    if key not in _PROVENANCE:
        p = _json.loads(_dashpot.provenance(law, **params))
        _PROVENANCE[key] = (p["params"], p)
    return _PROVENANCE[key]


def calibrate(law: str, restitution: float, v0: float = 1.0, *, contact_time: Optional[float] = None,
              diameter: float = 0.01, density: float = 1500.0, young: float = 6e9, poisson: float = 0.3,
              wall: bool = False, end: Optional[str] = None, fit: Optional[str] = None,
              rtol: float = 1e-11, **fixed: float) -> Dict[str, Any]:
    """Fits ``law``'s parameters to a measured ``restitution`` (and ``contact_time``, s, through
    Young's modulus) at impact speed ``v0`` (m/s), as ``dashpot calibrate --json``: the other
    parameters fixed as keywords, the particle as in ``collide``, ``fit`` naming the parameter
    to fit (default: the law's only dissipation parameter), ``end`` the criterion (default: the
    law's own). Returns a dict: params (all, fitted included), method, the realized restitution
    and contact time with their residuals, young, collisions, provenance."""
    return _json.loads(_dashpot.calibrate(law, fixed, float(restitution), contact_time, float(v0),
                                          diameter, density, young, poisson, wall, end, fit, rtol))
