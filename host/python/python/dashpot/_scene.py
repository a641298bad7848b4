"""DEM scenes: the soft-sphere engine of ``dashpot dem``, run from Python with numpy views of
the particles' state."""

from __future__ import annotations

import json as _json
import os as _os
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Union

import numpy as _np

from . import _dashpot
from ._attrs import Native, View
from ._laws import _Named

LawSpec = Union[str, _Named, Mapping[str, Any]]


def _law_table(what: str, spec: LawSpec) -> Dict[str, Any]:
    """A law given by name, as a law object (``ContactLaw("hsd", eps=0.5)``) or as a dict
    ``{"name": ..., "params": {...}}``: the scene file's ``{name, params}`` table."""
    if isinstance(spec, str):
        return {"name": spec, "params": {}}
    if isinstance(spec, _Named):
        return {"name": spec.name, "params": dict(spec.params)}
    if isinstance(spec, Mapping) and "name" in spec:
        return {"name": spec["name"], "params": dict(spec.get("params", {}))}
    raise ValueError(f"{what} = {spec!r}: give a law name, a law (e.g. ContactLaw('hsd', eps=0.5)) "
                     "or a dict {'name': ..., 'params': {...}}")


def _rows(name: str, x: Any, n: Optional[int], width: Optional[int]) -> _np.ndarray:
    """``x`` as a float64 array of n rows (of ``width`` values each, or one value if None)."""
    try:
        a = _np.asarray(x, dtype=_np.float64)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{name}: cannot be read as float64 numbers ({e})") from None
    if width is None and a.ndim == 0 and n is not None:
        a = _np.full(n, float(a))
    want = (a.shape[0] if n is None and a.ndim >= 1 else n,) + (() if width is None else (width,))
    if a.shape != want:
        raise ValueError(f"{name} has shape {a.shape}: {want} expected (one row per particle)")
    return a


class Scene:
    """A soft-sphere DEM scene on dashpot's engine (the one ``dashpot dem --scene`` runs):
    disks (``dimension=2``) or spheres (3), every contact through the laws' batch calls.

    Build it from keywords (the tables of a scene file; see docs/dem.md) or from a file with
    ``Scene.from_toml(path)``::

        sim = dashpot.Scene(dimension=3, positions=x, velocities=v, diameters=d,
                            law=dashpot.ContactLaw("hsd", eps=0.5), young=1e8, poisson=0.3,
                            density=2500.0, gravity=[0, 0, -9.81],
                            walls=[{"point": [0, 0, 0], "normal": [0, 0, 1]}])
        sim.run(0.1, every=1e-3, callback=lambda s: frames.append(s.positions.copy()))

    Keywords: ``positions`` (N, D) in m, ``diameters`` (N,) in m, ``velocities`` (N, D) in
    m/s (default 0), ``angular_velocities`` (N,) in 2D or (N, 3) in 3D, rad/s; ``law`` the
    contact law, ``tangential``, ``rolling``, ``twisting`` optional laws (each a name, a law
    object or ``{"name", "params"}``); the material ``young`` (Pa), ``poisson``, ``density``
    (kg/m³), ``disk_mass`` (2D: ``"sphere"`` or ``"disk"``); ``heat`` a heat-conduction law
    (sdk 0.4: the contacts conduct heat), with ``heat_capacity`` (J/(kg·K), or a species'
    ``heat_capacity``) and ``temperatures`` (K, one per particle or one for all; walls conduct
    when given a ``temperature``, K or ``{"mean", "amplitude", "frequency"}``; a ``generate``
    table takes a ``temperature``); ``gravity`` (m/s², D values);
    ``species``, a list of ``{"name", "young", "poisson", "density"}`` (instead of ``young``,
    ``poisson``, ``density``), with ``particle_species`` (one name per particle, or one for
    all) and ``pairs``, a list of ``{"species": [a, b], "law", "tangential", "rolling",
    "twisting"}`` (or ``{"species": a, "wall": K, ...}``) giving the laws of pairs of species
    (the top-level laws are the default of every pair not named; see docs/dem.md);
    ``duration`` (s), the scene's end time (what ``run()`` without an argument runs to); ``dt``
    (s), ``steps_per_collision``, ``impact_speed`` (m/s), ``skin`` (m) for the step and the
    neighbour list; ``box`` ``{"lo", "hi", "periodic", "bounded"}``; ``walls``, a list of
    ``{"point", "normal", "motion"}``; ``generate``, a random packing ``{"count", "diameter",
    "lo", "hi", "speed", "seed"}``; ``allow_initial_overlap``; ``energy`` (default ``True``:
    the energy accounting by family; ``False`` skips the laws' energy functions, and
    ``energy()`` then gives ``None`` for ``elastic``, ``dissipated`` and ``initial``). Every value
    is checked as the scene file's is; a refusal is a ``ValueError`` naming the key and the value.

    The state is read through read-only numpy views that follow the run without copies:
    ``positions``, ``velocities``, ``forces`` (contact forces of the last step, N, gravity
    excluded), ``angular_velocities``, ``torques``, ``radii``, ``masses``, ``inertia``, and with
    a heat law ``temperatures`` (K) and ``heat_capacities`` (J/K); ``heat()`` gives the thermal
    books. Copy
    what you keep (``sim.positions.copy()``), and do not read them from another thread while
    ``run`` steps."""

    def __init__(self, dimension: int = 3, *, positions: Any = None, diameters: Any = None,
                 velocities: Any = None, angular_velocities: Any = None,
                 law: Optional[LawSpec] = None, tangential: Optional[LawSpec] = None,
                 rolling: Optional[LawSpec] = None, twisting: Optional[LawSpec] = None,
                 heat: Optional[LawSpec] = None, heat_capacity: Optional[float] = None,
                 temperatures: Any = None,
                 young: Optional[float] = None, poisson: Optional[float] = None,
                 density: Optional[float] = None, disk_mass: Optional[str] = None,
                 species: Optional[Sequence[Mapping[str, Any]]] = None,
                 pairs: Optional[Sequence[Mapping[str, Any]]] = None,
                 particle_species: Any = None, gravity: Optional[Sequence[float]] = None,
                 duration: Optional[float] = None, dt: Optional[float] = None,
                 steps_per_collision: Optional[float] = None, impact_speed: Optional[float] = None,
                 skin: Optional[float] = None, box: Optional[Mapping[str, Any]] = None,
                 walls: Optional[Sequence[Mapping[str, Any]]] = None,
                 generate: Union[None, Mapping[str, Any], Sequence[Mapping[str, Any]]] = None,
                 allow_initial_overlap: bool = False, energy: bool = True) -> None:
        spec: Dict[str, Any] = {"dimension": int(dimension)}
        material = {k: v for k, v in [("young", young), ("poisson", poisson), ("density", density),
                                      ("disk_mass", disk_mass), ("heat_capacity", heat_capacity)]
                    if v is not None}
        if species is None:
            if any(v is None for v in (young, poisson, density)):
                raise ValueError("young, poisson, density: give the particles' material (Pa, ratio, kg/m³), "
                                 "or species=[{'name', 'young', 'poisson', 'density'}, ...]")
            spec["material"] = material
        else:
            if material:
                raise ValueError(f"{', '.join(material)} and species both given: with species, each species "
                                 "gives its own material")
            spec["species"] = [dict(sp) for sp in species]
        for key, law_spec in [("law", law), ("tangential", tangential), ("rolling", rolling),
                              ("twisting", twisting), ("heat", heat)]:
            if law_spec is not None:
                spec[key] = _law_table(key, law_spec)
        if pairs:
            spec["pair"] = [self._pair_table(k, p) for k, p in enumerate(pairs)]
        given_duration = duration is not None
        # (the scene file needs a duration; without one, run() needs its own)
        spec["duration"] = duration if given_duration else 1.0
        for key, value in [("gravity", gravity), ("dt", dt), ("steps_per_collision", steps_per_collision),
                           ("impact_speed", impact_speed), ("skin", skin), ("box", box), ("generate", generate)]:
            if value is not None:
                spec[key] = value
        if walls:
            spec["wall"] = [dict(w) for w in walls]
        if allow_initial_overlap:
            spec["allow_initial_overlap"] = True
        if not energy:
            spec["energy"] = False
        spec["particle"] = self._particles(int(dimension), positions, diameters, velocities, angular_velocities,
                                           particle_species)
        if temperatures is not None:
            t = _rows("temperatures", temperatures, len(spec["particle"]), None)
            for p, ti in zip(spec["particle"], t):
                p["temperature"] = float(ti)
        self._bind(_dashpot.Scene.from_spec(spec), duration if given_duration else None)

    @staticmethod
    def _pair_table(k: int, p: Mapping[str, Any]) -> Dict[str, Any]:
        """A ``[[pair]]`` table: ``species`` (one name or two), optional ``wall`` (an index or a
        name, or a list), and law specs ``law``, ``tangential``, ``rolling``, ``twisting``."""
        out: Dict[str, Any] = {}
        for key, value in p.items():
            if key in ("law", "tangential", "rolling", "twisting", "heat"):
                out[key] = _law_table(f"pairs[{k}].{key}", value)
            else:
                out[key] = value
        return out

    @staticmethod
    def _particles(dim: int, positions: Any, diameters: Any, velocities: Any,
                   angular_velocities: Any, species: Any = None) -> List[Dict[str, Any]]:
        if positions is None:
            if diameters is not None or velocities is not None or species is not None:
                raise ValueError("positions: give the particles' positions (N, D) with their diameters")
            return []
        x = _rows("positions", positions, None, dim)
        n = x.shape[0]
        if diameters is None:
            raise ValueError("diameters: give one diameter (m) per particle, or one for all")
        d = _rows("diameters", diameters, n, None)
        v = None if velocities is None else _rows("velocities", velocities, n, dim)
        w = None if angular_velocities is None else _rows(
            "angular_velocities", angular_velocities, n, None if dim == 2 else 3)
        if species is None or isinstance(species, str):
            names = None if species is None else [species] * n
        else:
            names = [str(x) for x in species]
            if len(names) != n:
                raise ValueError(f"particle_species has {len(names)} names: {n} expected (one per particle)")
        out = []
        for i in range(n):
            p: Dict[str, Any] = {"position": x[i].tolist(), "diameter": float(d[i])}
            if v is not None:
                p["velocity"] = v[i].tolist()
            if w is not None:
                p["angular_velocity"] = w[i].tolist()
            if names is not None:
                p["species"] = names[i]
            out.append(p)
        return out

    def _bind(self, inner: Any, duration: Optional[float]) -> None:
        self._inner = inner
        self._duration = duration
        self._views: Dict[str, _np.ndarray] = {}

    @classmethod
    def from_toml(cls, path: Union[str, "_os.PathLike[str]"]) -> "Scene":
        """The scene of a scene file (the TOML ``dashpot dem --scene`` reads; see docs/dem.md).
        ``run()`` then runs to its ``duration``, and ``result()`` gives what ``dashpot dem
        --scene FILE --json`` prints, to the bit."""
        sim = cls.__new__(cls)
        inner = _dashpot.Scene.from_toml(_os.fspath(path))
        sim._bind(inner, inner.duration)
        return sim

    dimension = Native[int]("2 (disks) or 3 (spheres).")
    time = Native[float]("Simulated time (s).")
    steps = Native[int]("Steps taken since the start.")
    dt = Native[float]("The time step (s), given or chosen from the contact time (see ``step_choice``).")
    positions = View("Positions (m), shape (N, D): a read-only view of the engine's array (wrapped into the box "
                     "along periodic axes at each neighbour-list rebuild).")
    velocities = View("Velocities (m/s), shape (N, D): a read-only view.")
    forces = View("Contact forces of the last step (N, gravity excluded), shape (N, D): a read-only view.")
    angular_velocities = View("Angular velocities (rad/s): shape (N,) in 2D (about z), (N, 3) in 3D; read-only.")
    torques = View("Contact torques of the last step (N·m), laid out as ``angular_velocities``; read-only.")
    radii = View("Radii (m), shape (N,).")
    masses = View("Masses (kg), shape (N,).")
    inertia = View("Moments of inertia (kg·m²), shape (N,).")
    temperatures = View("Temperatures (K), shape (N,), in a scene with a heat law: a read-only view.")
    heat_capacities = View("Heat capacities m c (J/K), shape (N,), in a scene with a heat law.")

    @property
    def species(self) -> List[str]:
        """Each particle's species, by name (empty names in a scene without species)."""
        return list(self._inner.particle_species())

    def to_toml(self, duration: Optional[float] = None) -> str:
        """The scene as a scene file (for ``dashpot dem --scene``), with ``duration`` (s) if
        given (needed when the scene was made without one)."""
        if duration is None and self._duration is None:
            raise ValueError("duration: the scene was made without one; give to_toml(duration=...)")
        return self._inner.to_toml(None if duration is None else float(duration))

    def __len__(self) -> int:
        return len(self._inner)

    @property
    def duration(self) -> Optional[float]:
        """The scene's own end time (s), or None."""
        return self._duration

    def step_choice(self) -> Dict[str, Any]:
        """How the step was chosen: ``dt`` (s), ``given``, the contact time ``collision_time`` (s)
        at ``impact_speed`` (m/s), and a ``warning`` (or None)."""
        return self._inner.step_choice()

    def run(self, duration: Optional[float] = None, *, every: Optional[float] = None,
            callback: Optional[Callable[["Scene"], Any]] = None) -> "Scene":
        """Runs for ``duration`` seconds of simulated time from now (default: to the scene's
        own ``duration``, from t = 0 as ``dashpot dem`` does); with ``callback``, calls
        ``callback(self)`` every ``every`` seconds of simulated time (rounded to whole steps; at
        the step count multiples of that) and at the end. The GIL is released while it steps;
        Ctrl-C stops it between blocks of steps (``KeyboardInterrupt``; the scene stays usable
        at the step reached). Returns the scene."""
        if duration is None:
            if self._duration is None:
                raise ValueError("duration: the scene was made without one; give run(duration)")
            t_end = self._duration
        else:
            if not (float(duration) >= 0.0 and _np.isfinite(duration)):
                raise ValueError(f"duration = {duration} s is out of range: it must be finite and >= 0")
            t_end = self.time + float(duration)
        never = 2 ** 63
        if every is None:
            self._inner._advance(t_end, never)
            if callback is not None:
                callback(self)
            return self
        if not (float(every) > 0.0 and _np.isfinite(every)):
            raise ValueError(f"every = {every} s is out of range: it must be finite and > 0")
        k = max(1, int(round(float(every) / self.dt)))
        while True:
            before = self.steps
            stop = (before // k + 1) * k
            self._inner._advance(t_end, stop)
            if self.steps == before:
                break
            if callback is not None:
                callback(self)
            if self.steps < stop:
                break
        return self

    def check(self, sample: float = 1.0) -> Dict[str, Any]:
        """What ``dashpot dem --scene FILE --check`` estimates of this scene's run from t = 0 to
        its ``duration``, before running it: ``steps``, ``dt`` (s), the peak memory
        ``memory_bytes`` (with ``memory_parts`` and ``memory_available_bytes``) and the wall time
        ``wall_seconds``, from a timed sample of about ``sample`` seconds of the scene's own steps
        on this machine (run on a second engine built from the scene: this one is not touched).
        A run that cannot fit or would never end raises ``ValueError`` naming why."""
        if self._duration is None:
            raise ValueError("duration: the scene was made without one; a check estimates the run to it")
        return _json.loads(self._inner._check(float(sample)))

    def _view(self, which: str) -> _np.ndarray:
        v = self._views.get(which)
        if v is None:
            v = self._views[which] = self._inner._view(which)
        return v

    def energy(self) -> Dict[str, Any]:
        """The energies now (J): ``translational``, ``rotational``, ``gravity`` and their
        ``total``; the ``elastic`` energy stored in the contacts; what each family of laws
        ``dissipated`` since the start (``normal``, ``tangential``, ``rolling``, ``twisting``,
        ``total``; None for a law that does not report it); ``initial``, the total and the
        elastic energy at the start; ``wall_work``, the work moving walls did on the particles.
        Their balance: initial + wall_work ≈ total + elastic + dissipated."""
        return self._inner.energy()

    def heat(self) -> Optional[Dict[str, Any]]:
        """The thermal books now, in a scene with a heat law (else None): ``thermal`` Σ m c T
        (J), ``thermal_initial``, ``wall_heat`` (the heat the walls gave, J), ``balance``
        (thermal − initial − wall heat: 0 to rounding), ``stability_limit`` (the smallest
        m c/ΣH met, s; None before any contact conducted) and ``warning`` (when dt exceeds it)."""
        return self._inner.heat()

    def result(self) -> Dict[str, Any]:
        """What ``dashpot dem --scene FILE --json`` prints after the same steps: the particles,
        dt, steps, time, energies, contacts, the laws and their provenance, the energy balance;
        ``wall_seconds`` and ``particle_steps_per_second`` measure the runs made here."""
        return _json.loads(self._inner.result())

    def __repr__(self) -> str:
        return (f"<dashpot.Scene {self.dimension}D, {len(self)} particles, t = {self.time:.6g} s, "
                f"{self.steps} steps of {self.dt:.4g} s>")
