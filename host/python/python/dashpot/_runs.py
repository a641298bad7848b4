"""Runs as the CLI makes them: one collision (``collide``), collisions over grids (``sweep``),
a law fitted to a measured restitution (``calibrate``) and the vibrated bed (``bed``)."""

from __future__ import annotations

import json as _json
import os as _os
from typing import Any, Dict, Mapping, Optional, Sequence, Tuple, Union

import numpy as _np

from . import _dashpot

Grid = Union[str, Sequence[float], _np.ndarray]

_PROVENANCE: Dict[str, Tuple[Dict[str, Any], Dict[str, Any]]] = {}


def _provenance(law: str, params: Dict[str, float]) -> Tuple[Dict[str, Any], Dict[str, Any]]:
    """(params, provenance) of a law as the CLI's JSON gives them, computed once per law and
    parameters (the dicts are shared between results: copy them before changing them)."""
    key = law + repr(sorted(params.items()))
    if key not in _PROVENANCE:
        p = _json.loads(_dashpot.provenance(law, **params))
        _PROVENANCE[key] = (p["params"], p)
    return _PROVENANCE[key]


def collide(law: str, v0: Union[float, Sequence[float], _np.ndarray] = 1.0, *, diameter: float = 0.01,
            density: float = 1500.0, young: float = 6e9, poisson: float = 0.3, wall: bool = False,
            end: Optional[str] = None, rtol: float = 1e-11, record: bool = False,
            **params: float) -> Dict[str, Any]:
    """One head-on collision, as ``dashpot collide --json`` computes it: ``law`` with its
    parameters as keywords, a sphere (``diameter`` m, ``density`` kg/m³, ``young`` Pa,
    ``poisson``; defaults: Antypov & Elliott's MCC granule) against an identical sphere or a
    ``wall``, impact speed ``v0`` (m/s); ``end`` is ``"overlap"`` (δ returns to 0) or
    ``"force"`` (F returns to 0), by default the criterion the law declares (the one
    ``calibrate`` fits it by, so that a calibrated law reproduces its target here); ``rtol``
    the integrator's relative tolerance per step, in [1e-14, 1e-3].

    Returns a dict: restitution, contact_time (s), max_overlap (m), max_overlap_time (s),
    stuck (adhesive laws), tensile_peak (N), steps, force_evals, pair, params, provenance (its
    plugin, param_sources and shadows shared by the results of the same law: copy before
    changing them);
    with ``record=True`` also the trajectory as arrays ``t`` (s), ``delta`` (m), ``rate``
    (m/s), ``force`` (N). The GIL is released while it runs.

    With ``v0`` a 1-D array of speeds, the collisions of a restitution curve: the same dict
    with a float64 array per observable, one value per speed (``stuck`` bool, ``steps`` and
    ``force_evals`` int64, ``tensile_peak`` NaN where the law never pulled), each value the
    bits of the single collision at that speed. A law without history runs them in lockstep,
    its force evaluations for all in one call, several times faster than one call per speed:
    the form for fitting a law to a measured ε(v). Any collision that fails raises
    ``ValueError`` naming its speed; Ctrl-C stops a long curve (``KeyboardInterrupt``)."""
    body = (diameter, density, young, poisson, wall)
    if _np.ndim(v0) == 0:
        return _dashpot.collide(law, params, float(v0), body, end, rtol, record)
    if record:
        raise ValueError("record=True records one collision's trajectory: give v0 as one speed, not an array")
    return _dashpot.collide_curve(law, params, _speeds(v0), body, end, rtol)


def _speeds(v0: Any) -> _np.ndarray:
    """Impact speeds as a contiguous float64 array (no copy when they are one), or ValueError."""
    a = _np.asarray(v0)
    if a.ndim != 1:
        raise ValueError(f"v0 has shape {a.shape}: give one speed or a 1-D array of speeds (m/s)")
    if a.dtype.kind not in "fiu":
        raise ValueError(f"v0 has dtype {a.dtype}: the impact speeds must be real numbers (m/s)")
    return _np.ascontiguousarray(a, dtype=_np.float64)


def sweep(law: str, v0: Grid = "1e-3:10:41", *, vary: Optional[Mapping[str, Grid]] = None,
          diameter: float = 0.01, density: float = 1500.0, young: float = 6e9, poisson: float = 0.3,
          wall: bool = False, end: Optional[str] = None, rtol: float = 1e-11,
          **params: float) -> Dict[str, Any]:
    """Collisions over a grid of impact speeds ``v0`` (m/s) and of law parameters, as
    ``dashpot sweep`` runs them (in parallel) and in its order: every v0 for the first set of
    parameters, then the next. A grid is a sequence of numbers or the CLI's
    ``START:STOP:COUNT[:log|lin]`` (or ``"a,b,c"``); ``vary`` maps parameter names to grids (the
    sweep is the full product); the other parameters are keywords; the particle, ``end`` and
    ``rtol`` as in ``collide``.

    Returns a dict of columns, one value per collision, as the CLI's CSV: ``law`` and ``end``
    (strings), each parameter by name, ``v0``, ``restitution``, ``contact_time`` (s),
    ``max_overlap`` (m), ``max_overlap_time`` (s) as float64 arrays, and ``provenance``.
    The GIL is released while it runs; Ctrl-C stops it (``KeyboardInterrupt``)."""
    vary_items = [(str(k), v if isinstance(v, str) else _np.asarray(v, dtype=_np.float64).tolist())
                  for k, v in (vary or {}).items()]
    v0_arg = v0 if isinstance(v0, str) else _np.asarray(v0, dtype=_np.float64).reshape(-1).tolist()
    body = (float(diameter), float(density), float(young), float(poisson), bool(wall))
    names, values, results, end_used = _dashpot.sweep(law, params, v0_arg, vary_items, body, end, float(rtol))
    vals = _np.array(values, dtype=_np.float64).reshape(len(results), len(names))
    res = _np.array(results, dtype=_np.float64).reshape(len(results), 5)
    out: Dict[str, Any] = {"law": law, "end": end_used}
    for k, name in enumerate(names):
        out[name] = _np.ascontiguousarray(vals[:, k])
    for k, name in enumerate(["v0", "restitution", "contact_time", "max_overlap", "max_overlap_time"]):
        out[name] = _np.ascontiguousarray(res[:, k])
    out["provenance"] = _provenance(law, params)[1]
    return out


def calibrate(law: str, restitution: Optional[float] = None, v0: float = 1.0, *,
              contact_time: Optional[float] = None, data: Any = None,
              diameter: float = 0.01, density: float = 1500.0, young: float = 6e9, poisson: float = 0.3,
              wall: bool = False, end: Optional[str] = None, fit: Optional[str] = None,
              rtol: float = 1e-11, **fixed: float) -> Dict[str, Any]:
    """Fits ``law``'s parameters to a measured ``restitution`` (and ``contact_time``, s, through
    Young's modulus) at impact speed ``v0`` (m/s), as ``dashpot calibrate --json``: the other
    parameters fixed as keywords, the particle as in ``collide``, ``fit`` naming the parameter
    to fit (default: the law's only dissipation parameter), ``end`` the criterion (default: the
    law's own). Returns a dict: params (all, fitted included), method, the realized restitution
    and contact time with their residuals, young, collisions, provenance. A fit that does not
    reproduce its target (restitution within 1e-9, contact time within 1e-9 relative; 100 rtol
    when coarser) raises ``ValueError`` naming the target, the value reached and why.

    With ``data`` instead of ``restitution``: a measured curve, as ``dashpot calibrate --data``,
    fitted by least squares: an array of rows v0 (m/s), e [, contact time (s)] (shape (n, 2) or
    (n, 3)) or the path of such a CSV file (a header line allowed); ``fit`` may name several
    parameters, comma-separated (default: the dissipation parameter, and the stiffness when
    contact times are given). Returns a dict: params, fitted (name, value, std_error of each
    fitted parameter), points (each with its fitted values and residuals), ``residuals`` (the
    restitution residuals, fitted − measured, as an array), rms, rms_contact_time, iterations,
    collisions, provenance."""
    body = (diameter, density, young, poisson, wall)
    if data is not None:
        if restitution is not None or contact_time is not None:
            raise ValueError("give either data (a measured curve) or restitution [and contact_time], not both")
        if isinstance(data, (str, _os.PathLike)):
            rows, path = None, _os.fspath(data)
        else:
            a = _np.asarray(data, dtype=_np.float64)
            if a.ndim != 2 or a.shape[1] not in (2, 3):
                raise ValueError(f"data has shape {a.shape}: give rows of v0 (m/s), e [, contact time (s)], "
                                 "shape (n, 2) or (n, 3), or the path of a CSV file")
            rows, path = a.tolist(), None
        out = _json.loads(_dashpot.calibrate_curve(law, fixed, rows, path, body, end, fit, rtol))
        out["residuals"] = _np.array([p["residual"] for p in out["points"]], dtype=_np.float64)
        return out
    if restitution is None:
        raise ValueError("give the measured restitution (and v0), or a measured curve as data")
    return _json.loads(_dashpot.calibrate(law, fixed, float(restitution), contact_time, float(v0), body, end, fit,
                                          rtol))


def _arg(x: Any) -> str:
    """A value as the CLI reads it (floats exactly: ``repr`` is the shortest round trip)."""
    if isinstance(x, bool):
        raise ValueError(f"{x!r}: a number or a name was expected")
    if isinstance(x, (int, _np.integer)):
        return str(int(x))
    if isinstance(x, (float, _np.floating)):
        return repr(float(x))
    return str(x)


def bed(layers: float, freq: float, *, restitution: Optional[str] = None, law: Optional[str] = None,
        params: Optional[Mapping[str, float]] = None, engine: Optional[str] = None,
        tangential: Union[str, float, None] = None, tparams: Optional[Mapping[str, float]] = None,
        rolling: Optional[str] = None, rparams: Optional[Mapping[str, float]] = None,
        young: Optional[float] = None, poisson: Optional[float] = None, dt: Optional[float] = None,
        steps_per_collision: Optional[float] = None, gravity: Optional[float] = None,
        amplitude: Optional[float] = None, width: Optional[float] = None,
        diameter: Optional[float] = None, mass: Optional[float] = None,
        headroom: Optional[float] = None, cycles: Optional[float] = None,
        transient: Optional[float] = None, tc: Optional[float] = None, seed: Optional[int] = None,
        seeds: Optional[int] = None) -> Dict[str, Any]:
    """McNamara & Falcon's vibrated bed, as ``dashpot bed --json`` runs it; returns its JSON as
    a dict (lid pressure, collision rate, mean impulse, temperature with their standard
    errors, the configuration, the counters, provenance).

    ``layers`` n (N = n L/d disks), piston frequency ``freq`` (Hz). The event-driven engine
    takes a ``restitution`` law (e.g. ``"mcnamara-falcon"``, ``"constant"``, or a contact law as
    ``"from:NAME"``) and a tangential restitution ``tangential`` r_t; the DEM engine
    (``engine="dem"``, the default when ``law`` is given) a contact ``law``, a ``tangential``
    law by name, a ``rolling`` law. ``params``, ``tparams``, ``rparams``: the laws' parameters
    (``--set``, ``--tset``, ``--rset``). The other keywords are the CLI's options of the same
    name, with its defaults: ``gravity`` 9.8 m/s², ``amplitude`` 0.025 m, ``width`` 0.2 m,
    ``diameter`` 0.002 m, ``mass`` 3.27e-5 kg, ``headroom`` 0.015 m, ``cycles`` 200 and
    ``transient`` 50 periods, ``tc`` (s, TC model), ``seed`` 1, ``seeds`` 1; DEM: ``young``,
    ``poisson``, ``dt`` (s), ``steps_per_collision``.

    Raises ``ValueError`` for a value the CLI refuses (named), ``RuntimeError`` for a run that
    went wrong (inelastic collapse, an overlap). The GIL is released while it runs; Ctrl-C
    stops it (``KeyboardInterrupt``)."""
    if engine is None and law is not None and restitution is None:
        engine = "dem"
    argv = ["--layers", _arg(layers), "--freq", _arg(freq)]
    options = [("--engine", engine), ("--restitution", restitution), ("--law", law),
               ("--tangential", tangential), ("--rolling", rolling), ("--young", young),
               ("--poisson", poisson), ("--dt", dt), ("--steps-per-collision", steps_per_collision),
               ("--gravity", gravity), ("--amplitude", amplitude), ("--width", width),
               ("--diameter", diameter), ("--mass", mass), ("--headroom", headroom),
               ("--cycles", cycles), ("--transient", transient), ("--tc", tc), ("--seed", seed),
               ("--seeds", seeds)]
    for flag, value in options:
        if value is not None:
            argv += [flag, _arg(value)]
    for flag, table in [("--set", params), ("--tset", tparams), ("--rset", rparams)]:
        for k, v in (table or {}).items():
            argv += [flag, f"{k}={_arg(v)}"]
    return _json.loads(_dashpot.bed(argv))
