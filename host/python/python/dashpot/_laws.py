"""The laws on numpy arrays: contact (normal), tangential, rolling, twisting, heat and
restitution laws, chosen by name, with their parameters as keywords, bound to a pair of materials."""

from __future__ import annotations

import json as _json
import os as _os
from typing import Any, Dict, Generic, List, Optional, Tuple, TypeVar, Union

import numpy as _np

from . import _dashpot
from ._attrs import Native

Array = _np.ndarray


def laws() -> List[Dict[str, Any]]:
    """Every law found: dicts with name, kind, summary, doc, plugin, params (each with name,
    unit, default and valid range), as ``dashpot laws --json`` lists them."""
    return _json.loads(_dashpot.laws())


def load_plugin(path: Union[str, "_os.PathLike[str]"]) -> None:
    """Loads the plugin library at ``path`` (a third-party law, say); its laws join those
    already found (a name already known keeps its first law, as the CLI does).

    Raises ``PluginError`` if the file is not a dashpot plugin of a compatible sdk."""
    _dashpot.load_plugin(_os.fspath(path))


def _f64(name: str, x: Any, n: Optional[int] = None, of: str = "delta") -> Array:
    """``x`` as a contiguous one-dimensional float64 array (no copy when it already is one)."""
    try:
        a = _np.ascontiguousarray(x, dtype=_np.float64)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{name}: cannot be read as float64 numbers ({e})") from None
    if a.ndim == 0:
        a = a.reshape(1)
    if a.ndim != 1:
        raise ValueError(f"{name} has shape {a.shape}: it must be one-dimensional, one value per contact")
    if n is not None and a.shape[0] != n:
        raise ValueError(f"{name} has {a.shape[0]} values, {of} {n}: one value per contact")
    return a


def _vectors(name: str, x: Any, n: int) -> Array:
    """``x`` as a contiguous float64 array of shape (n, 3), flattened (no copy when it is one)."""
    try:
        a = _np.ascontiguousarray(x, dtype=_np.float64)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{name}: cannot be read as float64 numbers ({e})") from None
    if a.shape != (n, 3):
        raise ValueError(f"{name} has shape {a.shape}: it must be ({n}, 3), one vector per contact")
    return a.reshape(-1)


def _history(history: Any) -> Array:
    """The caller's history array, flattened without a copy (it is updated in place)."""
    if not (isinstance(history, _np.ndarray) and history.dtype == _np.float64 and history.flags.c_contiguous
            and history.flags.writeable):
        raise ValueError("history must be a writeable, C-contiguous float64 numpy array of shape "
                         "(N, history_slots), zeros at first touch; it is updated in place")
    return history.reshape(-1)


B = TypeVar("B")


class _Named:
    """A law by name with its parameters as keywords (checked by the law when it is used)."""

    def __init__(self, name: str, **params: float) -> None:
        self.name = name
        self.params = dict(params)

    def __repr__(self) -> str:
        args = "".join(f", {k}={v!r}" for k, v in self.params.items())
        return f"{type(self).__name__}({self.name!r}{args})"

    def provenance(self) -> Dict[str, Any]:
        """The law's plugin file, versions and every parameter, as the CLI's JSON gives them."""
        return _json.loads(_dashpot.provenance(self.name, **self.params))


class _Law(_Named, Generic[B]):
    """A law that binds to a pair of materials."""

    _bind: Any = staticmethod(_dashpot.bind_contact)
    _bound: Any = None
    _kind = "contact"

    def __init__(self, name: str, **params: float) -> None:
        """Raises ``ValueError`` here, not at ``bind``, for an unknown law or parameter (with "did
        you mean"), a law of another kind, or a value out of its valid range."""
        super().__init__(name, **params)
        _dashpot.check_law(type(self)._kind, self.name, **self.params)

    def bind(self, young: float, poisson: float, young2: Optional[float] = None,
             poisson2: Optional[float] = None, wall: bool = False) -> B:
        """The law for a pair of materials: Young's modulus ``young`` (Pa) and Poisson's ratio
        ``poisson`` of the first body; the second another sphere (``young2``, ``poisson2``,
        default the first's) or, with ``wall=True``, a rigid wall. Raises ``ValueError`` for an
        unknown law or parameter (with "did you mean"), a law of another kind, or a value out of
        range."""
        inner = type(self)._bind(self.name, self.params, float(young), float(poisson), young2, poisson2, wall)
        return type(self)._bound(inner)


class _Bound:
    """A law bound to a pair of materials."""

    name = Native[str]("The law's name.")
    history_slots = Native[int]("History values the law keeps per contact (0 for a memoryless law).")
    reads_context = Native[bool]("Whether the law reads the normal law's context (sdk 0.4): then pass it the "
                                 "contexts of ``BoundContactLaw.force_context`` (tangential, rolling, "
                                 "twisting laws).")

    def __init__(self, inner: Any) -> None:
        self._inner = inner

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.name!r}, {self.history_slots} history slots>"


class BoundContactLaw(_Bound):
    """A contact (normal) law bound to a pair of materials (see ``ContactLaw.bind``)."""

    def force(self, delta: Any, rate: Any, mass: Any, radius: Any, history: Optional[Array] = None,
              out: Optional[Array] = None) -> Array:
        """Normal forces (N, > 0 repulsive) of N contacts: overlaps ``delta`` (m), rates
        ``rate`` (m/s, > 0 approaching), effective masses ``mass`` (kg) and radii ``radius``
        (m), each an array of N values (contiguous float64 arrays are used without a copy). A
        law with history needs ``history``, a float64 array of shape (N, history_slots), zeros
        at first touch, which it updates in place. ``out``, a float64 array of N values,
        receives the forces instead of a new array (a loop over steps then allocates nothing).
        The GIL is released during the call."""
        d = _f64("delta", delta)
        n = d.shape[0]
        args = (d, _f64("rate", rate, n), _f64("mass", mass, n), _f64("radius", radius, n))
        if out is not None and not (isinstance(out, _np.ndarray) and out.dtype == _np.float64
                                    and out.ndim == 1 and out.flags.c_contiguous and out.flags.writeable):
            raise ValueError("out must be a writeable, contiguous one-dimensional float64 numpy array")
        h = None if history is None else _history(history)
        return self._inner.force(args, h, out)

    def force_energy(self, delta: Any, rate: Any, mass: Any, radius: Any,
                     history: Optional[Array] = None) -> Tuple[Array, Optional[Array], Optional[Array], Array]:
        """As ``force``, with the energy outputs of sdk 0.3: ``(force, power, elastic, reach)``,
        each of shape (N,): the forces (N), the power each contact dissipates (W, ≥ 0), the
        elastic energy it stores (J), ``None`` both for a law that does not report them, and its
        reach (m: the contact lasts while δ > −reach; 0 but for adhesive laws)."""
        d = _f64("delta", delta)
        n = d.shape[0]
        h = None if history is None else _history(history)
        return self._inner.force((d, _f64("rate", rate, n), _f64("mass", mass, n), _f64("radius", radius, n)), h,
                                 None, True)


    def force_context(self, delta: Any, rate: Any, mass: Any, radius: Any,
                      history: Optional[Array] = None) -> Tuple[Array, Array]:
        """As ``force``, with each contact's normal context (sdk 0.4): ``(force, context)``,
        ``context`` of shape (N, 3), per contact the contact radius a (m; JKR's own, positive past
        touching until rupture), the force the caps of the contact's other laws scale with (N)
        and the normal damping coefficient (N·s/m). A law that reports none of its own gives
        a = √(R max(δ, 0)), max(F, 0) and 0. Pass it to the tangential, rolling and twisting laws
        that read it (``reads_context``)."""
        d = _f64("delta", delta)
        n = d.shape[0]
        h = None if history is None else _history(history)
        context = _np.empty((n, 3))
        f = self._inner.force((d, _f64("rate", rate, n), _f64("mass", mass, n), _f64("radius", radius, n)), h,
                              None, False, context.reshape(-1))
        return f, context


def _contexts(context: Any, n: int) -> Optional[Array]:
    """The normal contexts of N contacts, shape (N, 3), flattened; ``None`` for the defaults."""
    if context is None:
        return None
    try:
        a = _np.ascontiguousarray(context, dtype=_np.float64)
    except (TypeError, ValueError) as e:
        raise ValueError(f"context: cannot be read as float64 numbers ({e})") from None
    if a.shape != (n, 3):
        raise ValueError(f"context has shape {a.shape}: it must be ({n}, 3), one (contact radius, cap force, "
                         "damping) per contact")
    return a.reshape(-1)


class ContactLaw(_Law[BoundContactLaw]):
    """Contact (normal) law ``name`` (see ``laws()``) with its parameters as keywords, checked
    by the law: ``ContactLaw("hsd", eps=0.3)``."""

    _bind = staticmethod(_dashpot.bind_contact)
    _bound = BoundContactLaw


class _BoundVector(_Bound):
    """A tangential or rolling law bound to a pair: vectors in, vectors out."""

    _velocity = "velocity"

    def force(self, dt: float, normal: Any, velocity: Any, normal_force: Any, delta: Any, mass: Any,
              radius: Any, history: Array, energy: bool = False, context: Any = None) -> Any:
        fn = _f64("normal_force", normal_force)
        n = fn.shape[0]
        r = self._inner.force(float(dt), _vectors("normal", normal, n), _vectors(self._velocity, velocity, n), fn,
                              _f64("delta", delta, n, "normal_force"), _f64("mass", mass, n, "normal_force"),
                              _f64("radius", radius, n, "normal_force"), _history(history), bool(energy),
                              _contexts(context, n))
        if energy:
            f, (p, e) = r
            return f.reshape(n, 3), p, e
        return r.reshape(n, 3)


class BoundTangentialLaw(_BoundVector):
    """A tangential (friction) law bound to a pair of materials (see ``TangentialLaw.bind``)."""

    def force(self, dt: float, normal: Any, velocity: Any, normal_force: Any, delta: Any, mass: Any,
              radius: Any, history: Array, energy: bool = False, context: Any = None) -> Any:
        """Tangential forces (N) on N contacts, shape (N, 3), over a step ``dt`` (s): unit
        normals ``normal`` (N, 3) from the partner to the particle, contact-point relative
        velocities ``velocity`` (N, 3, m/s), normal forces ``normal_force`` (N), overlaps
        ``delta`` (m), effective masses (kg) and radii (m); ``history``, a float64 array of
        shape (N, history_slots), zeros at first touch, is advanced in place. With
        ``energy=True``, returns ``(force, power, elastic)``: also the power each contact
        dissipates (W) and the elastic energy it stores (J), each (N,), ``None`` for a law that
        does not report them. ``context`` (N, 3): the normal law's contexts
        (``BoundContactLaw.force_context``), for a law that reads them (``reads_context``);
        ``None``, each contact's default."""
        return super().force(dt, normal, velocity, normal_force, delta, mass, radius, history, energy, context)


class BoundRollingLaw(_BoundVector):
    """A rolling-resistance law bound to a pair of materials (see ``RollingLaw.bind``)."""

    _velocity = "velocity (rolling)"

    def force(self, dt: float, normal: Any, velocity: Any, normal_force: Any, delta: Any, mass: Any,
              radius: Any, history: Array, energy: bool = False, context: Any = None) -> Any:
        """Rolling-resistance forces F_r (N) on N contacts, shape (N, 3), over a step ``dt``
        (s); the torque on the particle is R n̂ × F_r. Inputs: unit normals ``normal`` (N, 3)
        from the partner to the particle, rolling velocities ``velocity`` = R (ω_i − ω_j) × n̂
        (N, 3, m/s), normal forces (N), overlaps (m), effective masses (kg) and radii R (m);
        ``history`` (N, history_slots), zeros at first touch, advanced in place. With
        ``energy=True``, returns ``(force, power, elastic)`` as ``BoundTangentialLaw.force``;
        ``context`` as there."""
        return super().force(dt, normal, velocity, normal_force, delta, mass, radius, history, energy, context)


class BoundTwistingLaw(_Bound):
    """A twisting-resistance law bound to a pair of materials (see ``TwistingLaw.bind``)."""

    def torque(self, dt: float, normal: Any, rate: Any, normal_force: Any, delta: Any, mass: Any,
               radius: Any, history: Array, energy: bool = False, context: Any = None) -> Any:
        """Twisting torques M (N·m, about n̂, on the particle) on N contacts, shape (N,), over a
        step ``dt`` (s): unit normals ``normal`` (N, 3), twisting rates ``rate`` = (ω_i − ω_j)·n̂
        (N, rad/s), normal forces (N), overlaps (m), effective masses (kg) and radii (m);
        ``history`` (N, history_slots), zeros at first touch, advanced in place. With
        ``energy=True``, returns ``(torque, power, elastic)``; ``context`` as for
        ``BoundTangentialLaw.force``."""
        fn = _f64("normal_force", normal_force)
        n = fn.shape[0]
        r = self._inner.torque(float(dt), _vectors("normal", normal, n), _f64("rate", rate, n, "normal_force"), fn,
                               _f64("delta", delta, n, "normal_force"), _f64("mass", mass, n, "normal_force"),
                               _f64("radius", radius, n, "normal_force"), _history(history), bool(energy),
                               _contexts(context, n))
        if energy:
            t, (p, e) = r
            return t, p, e
        return r


class BoundHeatLaw(_Bound):
    """A heat-conduction law bound to a pair of materials (see ``HeatLaw.bind``; sdk 0.4)."""

    def heat(self, temperature: Any, normal_force: Any, delta: Any, radius: Any,
             history: Optional[Array] = None, context: Any = None, dt: float = 0.0) -> Tuple[Array, Array]:
        """``(heat, conductance)`` of N contacts, each shape (N,): the heat flow Q into particle
        i (W; its partner receives exactly −Q) and the conductance H (W/K). ``temperature`` is
        (N, 2), ``[T_i, T_j]`` per contact (K; a wall's temperature as T_j); normal forces (N),
        overlaps δ (m) and effective radii R_eff (m, R_i against a flat wall) N each.
        ``context``, the normal law's contexts (``BoundContactLaw.force_context``, (N, 3)),
        gives its contact radius a (JKR's own); without it a = √(R_eff max(δ, 0)). A law with
        history needs ``history`` (N, history_slots), advanced in place over ``dt`` (s).
        Integrate as LAMMPS's ``fix heat/flow``: T += dt Q / (m c)."""
        fn = _f64("normal_force", normal_force)
        n = fn.shape[0]
        try:
            t = _np.ascontiguousarray(temperature, dtype=_np.float64)
        except (TypeError, ValueError) as e:
            raise ValueError(f"temperature: cannot be read as float64 numbers ({e})") from None
        if t.shape != (n, 2):
            raise ValueError(f"temperature has shape {t.shape}: it must be ({n}, 2), [T_i, T_j] per contact")
        h = _history(history) if history is not None else _np.zeros(0)
        return self._inner.heat(float(dt), t.reshape(-1), fn, _f64("delta", delta, n, "normal_force"),
                                _f64("radius", radius, n, "normal_force"), h, _contexts(context, n))


class TangentialLaw(_Law[BoundTangentialLaw]):
    """Tangential (friction) law ``name`` (e.g. ``"mindlin"``) with its parameters as keywords."""

    _bind = staticmethod(_dashpot.bind_tangential)
    _bound = BoundTangentialLaw
    _kind = "tangential"


class RollingLaw(_Law[BoundRollingLaw]):
    """Rolling-resistance law ``name`` (e.g. ``"rolling-sds"``) with its parameters as keywords."""

    _bind = staticmethod(_dashpot.bind_rolling)
    _bound = BoundRollingLaw
    _kind = "rolling"


class TwistingLaw(_Law[BoundTwistingLaw]):
    """Twisting-resistance law ``name`` (e.g. ``"twisting-sds"``) with its parameters as keywords."""

    _bind = staticmethod(_dashpot.bind_twisting)
    _bound = BoundTwistingLaw
    _kind = "twisting"


class HeatLaw(_Law[BoundHeatLaw]):
    """Heat-conduction law ``name`` (e.g. ``"heat-radius"``, ``k=2.0``) with its parameters as
    keywords (sdk 0.4)."""

    _bind = staticmethod(_dashpot.bind_heat)
    _bound = BoundHeatLaw
    _kind = "heat"


class RestitutionLaw(_Named):
    """Restitution law ``name`` (e.g. ``"mcnamara-falcon"``) with its parameters as keywords,
    for a particle (``diameter`` m, ``density`` kg/m³, ``young`` Pa, ``poisson``; defaults:
    the MCC granule) against an identical one or a ``wall``."""

    def __init__(self, name: str, *, diameter: float = 0.01, density: float = 1500.0,
                 young: float = 6e9, poisson: float = 0.3, wall: bool = False, **params: float) -> None:
        super().__init__(name, **params)
        _dashpot.check_law("restitution", self.name, **self.params)
        self._pair = (float(diameter), float(density), float(young), float(poisson), bool(wall))

    def r(self, speeds: Any) -> Array:
        """The coefficient of restitution at each normal impact speed (m/s), shape (N,)."""
        return _dashpot.restitution(self.name, self.params, _f64("speeds", speeds), self._pair)
