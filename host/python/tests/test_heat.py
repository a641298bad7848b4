"""Heat laws (sdk 0.4) from Python: LAMMPS's heat radius/area conductances, Q_ji = -Q_ij to
the bit, two spheres relaxing as the discrete closed form (1 - dt/tau)^n under explicit Euler,
the normal law's contexts (JKR's contact radius past touching), and errors naming the bad input."""

import math

import numpy as np
import pytest

import dashpot

STEEL = (2.0e11, 0.3)


def test_heat_laws_are_listed_and_read_the_context():
    heat = {l["name"]: l for l in dashpot.laws() if l["kind"] == "heat"}
    assert {"heat-radius", "heat-area", "heat-radius-corrected"} <= set(heat)
    law = dashpot.HeatLaw("heat-radius", k=2.0).bind(*STEEL)
    assert law.reads_context and law.history_slots == 0


def test_radius_and_area_conductances_and_exact_antisymmetry():
    k, h = 2.0, 5.0e4
    t = np.array([[300.0, 350.0], [350.0, 300.0]])
    fn, d, r = np.ones(2), np.full(2, 1e-6), np.full(2, 5e-4)
    a = math.sqrt(5e-4 * 1e-6)
    for law, want in [(dashpot.HeatLaw("heat-radius", k=k), 2 * k * a),
                      (dashpot.HeatLaw("heat-area", h=h), h * math.pi * a * a)]:
        q, g = law.bind(*STEEL).heat(t, fn, d, r)
        assert g[0] == want and q[0] == want * 50.0
        assert q[1] == -q[0]


def test_two_spheres_relax_as_the_discrete_closed_form():
    law = dashpot.HeatLaw("heat-area", h=1e6).bind(*STEEL)
    c1, c2 = 0.016, 0.055
    reff, delta = 6e-4, 1e-6
    t1, t2 = 300.0, 350.0
    _, g = law.heat(np.array([[t1, t2]]), [1.0], [delta], [reff])
    tau = 1.0 / (g[0] * (1 / c1 + 1 / c2))
    dt = tau / 50
    for n in range(1, 101):
        q, _ = law.heat(np.array([[t1, t2]]), [1.0], [delta], [reff])
        t1 += dt * q[0] / c1
        t2 -= dt * q[0] / c2
        assert abs((t2 - t1) - 50.0 * (1 - dt / tau) ** n) <= 1e-12 * 50.0
    assert abs(c1 * t1 + c2 * t2 - (c1 * 300.0 + c2 * 350.0)) <= 1e-13 * (c1 * 300.0 + c2 * 350.0)


def test_jkr_contexts_give_conduction_past_touching():
    jkr = dashpot.ContactLaw("jkr", w=10.0).bind(*STEEL)
    heat = dashpot.HeatLaw("heat-radius", k=10.0).bind(*STEEL)
    hist = np.zeros((1, jkr.history_slots))
    for d in [1e-7, 0.0, -1e-8]:
        f, ctx = jkr.force_context([d], [0.0], [1e-4], [1e-3], history=hist)
        q, g = heat.heat(np.array([[300.0, 310.0]]), f, [d], [1e-3], context=ctx)
        assert g[0] == 20.0 * ctx[0, 0] and q[0] > 0.0


def test_bad_input_names_it():
    law = dashpot.HeatLaw("heat-radius", k=1.0).bind(*STEEL)
    with pytest.raises(ValueError, match=r"\(2, 2\)"):
        law.heat(np.zeros((3, 2)), [1.0, 1.0], [1e-6, 1e-6], [1e-3, 1e-3])
    with pytest.raises(ValueError, match=r"temperature\[1\]"):
        law.heat(np.array([[300.0, 301.0], [300.0, np.nan]]), [1.0, 1.0], [1e-6, 1e-6], [1e-3, 1e-3])
    with pytest.raises(ValueError, match="needs the conductivity k"):
        dashpot.HeatLaw("heat-radius").bind(*STEEL)


def _held_pair(**kw):
    """Two steel spheres at rest in contact, in zero gravity, conducting through heat-area."""
    return dashpot.Scene(dimension=3, positions=[[0.0, 0.0, 0.0], [0.002 - 2e-6, 0.0, 0.0]],
                         diameters=0.002, law="lsd", young=2e11, poisson=0.3, density=7800.0,
                         heat=dashpot.HeatLaw("heat-area", h=1e6), heat_capacity=500.0,
                         temperatures=[300.0, 400.0], gravity=[0.0, 0.0, 0.0],
                         allow_initial_overlap=True, duration=1e-5, **kw)


def test_a_scene_exposes_temperatures_as_views_and_closes_its_thermal_books():
    sim = _held_pair()
    t = sim.temperatures
    assert t.shape == (2,) and not t.flags.writeable
    assert list(t) == [300.0, 400.0]
    c = sim.heat_capacities
    m = 7800.0 * math.pi / 6.0 * 0.002**3
    assert np.allclose(c, m * 500.0, rtol=1e-15)
    books = sim.heat()
    assert books["thermal"] == pytest.approx(c[0] * 300.0 + c[1] * 400.0, rel=1e-15)
    sim.run(1e-5)
    # the same view, following the run: heat went from the hot sphere to the cold one
    assert t[0] > 300.0 and t[1] < 400.0
    assert c[0] * (t[0] - 300.0) == pytest.approx(-c[1] * (t[1] - 400.0), rel=1e-9)
    books = sim.heat()
    assert abs(books["balance"]) <= 1e-13 * books["thermal"] and books["wall_heat"] == 0.0
    assert books["warning"] is None
    # result() carries each particle's temperature and the books
    r = sim.result()
    assert r["particles"][1]["temperature"] == t[1]
    assert r["heat"]["thermal"] == books["thermal"]


def test_a_scene_without_heat_has_no_temperatures_and_bad_heat_input_is_refused():
    sim = dashpot.Scene(dimension=3, positions=[[0.0, 0.0, 0.001]], diameters=0.002, law="hsd",
                        young=1e7, poisson=0.3, density=2500.0)
    assert sim.heat() is None
    with pytest.raises(ValueError, match="no heat law"):
        sim.temperatures
    with pytest.raises(ValueError, match="heat_capacity is missing"):
        dashpot.Scene(dimension=3, positions=[[0.0, 0.0, 0.001]], diameters=0.002,
                      law="hsd", young=1e7, poisson=0.3, density=2500.0,
                      heat="heat-radius", temperatures=300.0)
    with pytest.raises(ValueError, match=r"particle\[1\].temperature = -5 K"):
        dashpot.Scene(dimension=3, positions=[[0.0, 0.0, 0.0], [0.01, 0.0, 0.0]], diameters=0.002,
                      law="hsd", young=1e7, poisson=0.3, density=2500.0, heat="heat-radius",
                      heat_capacity=500.0, temperatures=[300.0, -5.0])
