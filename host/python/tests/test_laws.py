"""The Python package against the CLI and against physics: the same plugins give the same bits
through numpy as through `dashpot eval` and `dashpot collide`, batches are invariant under
splitting, and every refusal is the right exception naming the value.

Run with the plugins and the CLI of a built checkout: `DASHPOT_PLUGIN_PATH=target/debug` and
`DASHPOT_BIN=target/debug/dashpot` (conftest.py sets both from the repository root)."""

import numpy as np
import pytest

import dashpot
from conftest import M_PAIR, MCC, R_PAIR


def test_laws_lists_every_shipped_law_with_its_schema():
    names = {l["name"]: l for l in dashpot.laws()}
    for n in ["lsd", "hsd", "kuwabara-kono", "thornton", "walton-braun", "jkr", "dmt", "mindlin"]:
        assert n in names, n
    assert names["hsd"]["kind"] == "contact"
    assert [p["name"] for p in names["hsd"]["params"]] == ["eps"]


def test_a_million_contacts_split_any_way_give_the_same_bits_and_hertz_when_undamped():
    rng = np.random.default_rng(7)
    n = 1_000_000
    delta = rng.uniform(0.0, 1e-5, n)
    rate = rng.uniform(-1.0, 1.0, n)
    mass = rng.uniform(1e-4, 1e-3, n)
    radius = rng.uniform(1e-3, 5e-3, n)
    b = dashpot.ContactLaw("hsd", eps=0.3).bind(**MCC)
    f = b.force(delta, rate, mass, radius)
    assert f.shape == (n,) and f.dtype == np.float64
    parts = np.concatenate([b.force(delta[i:i + 999], rate[i:i + 999], mass[i:i + 999], radius[i:i + 999])
                            for i in range(0, 20_000, 999)])
    assert np.array_equal(parts, f[:parts.shape[0]])
    out = np.empty(n)
    assert b.force(delta, rate, mass, radius, out=out) is out and np.array_equal(out, f)
    # at rate 0 HSD is Hertz: F = (4/3) E_eff √r δ^{3/2}
    e_eff = 6e9 / (2 * (1 - 0.3**2))
    f0 = b.force(delta, np.zeros(n), mass, radius)
    hertz = 4.0 / 3.0 * e_eff * np.sqrt(radius) * delta**1.5
    assert np.allclose(f0, hertz, rtol=1e-13, atol=0.0)


def test_a_law_with_history_updates_the_callers_history_in_place():
    b = dashpot.ContactLaw("thornton", py=1e8).bind(**MCC)
    k = b.history_slots
    assert k >= 1
    h = np.zeros((2, k))
    b.force([1e-5, 2e-5], [0.1, 0.1], [M_PAIR] * 2, [R_PAIR] * 2, history=h)
    assert np.all(h[:, 0] > 0.0)  # the largest overlap remembered
    with pytest.raises(ValueError, match="history"):
        b.force([1e-5], [0.1], [M_PAIR], [R_PAIR])


def test_hsd_realizes_its_restitution_and_records_its_trajectory():
    c = dashpot.collide("hsd", v0=1.0, eps=0.54, record=True)
    assert abs(c["restitution"] - 0.54) < 1e-8
    assert c["t"].shape == c["delta"].shape == c["force"].shape
    assert c["delta"][0] == 0.0 and abs(c["delta"][-1]) < 1e-12
    assert c["delta"].max() == pytest.approx(c["max_overlap"], rel=1e-6)


def test_refusals_name_the_value():
    with pytest.raises(ValueError, match="did you mean `hsd`"):
        dashpot.ContactLaw("hdd").bind(**MCC)
    with pytest.raises(ValueError, match="epsx"):
        dashpot.ContactLaw("hsd", epsx=0.5).bind(**MCC)
    with pytest.raises(ValueError, match="2"):
        dashpot.ContactLaw("hsd", eps=2.0).bind(**MCC)
    with pytest.raises(ValueError, match="-1"):
        dashpot.ContactLaw("hsd", eps=0.5).bind(young=-1.0, poisson=0.3)
    b = dashpot.ContactLaw("hsd", eps=0.5).bind(**MCC)
    with pytest.raises(ValueError, match="3 values, delta 2"):
        b.force([1e-5, 1e-5], [0.0, 0.0], [1e-3, 1e-3, 1e-3], [1e-3, 1e-3])
    with pytest.raises(ValueError, match="float64"):
        b.force(["a"], [0.0], [1e-3], [1e-3])
    with pytest.raises(ValueError, match="nan|NaN"):
        b.force([float("nan")], [0.0], [1e-3], [1e-3])
    with pytest.raises(ValueError, match="v0 = -1"):
        dashpot.collide("hsd", v0=-1.0)
    with pytest.raises(ValueError, match="end = 'sideways'"):
        dashpot.collide("hsd", v0=1.0, end="sideways")


def test_a_file_that_is_not_a_plugin_is_a_plugin_error(tmp_path):
    p = tmp_path / "libnot_a_plugin.so"
    p.write_text("not a library")
    with pytest.raises(dashpot.PluginError, match="not a shared library"):
        dashpot.load_plugin(str(p))


def test_a_panicking_plugin_is_an_exception_and_python_carries_on():
    names = {l["name"] for l in dashpot.laws()}
    if "panicky" not in names:
        pytest.skip("the fault fixture plugin is not built")
    b = dashpot.ContactLaw("panicky", at=1e-6).bind(**MCC)
    with pytest.raises(RuntimeError, match="panic"):
        b.force([1e-5], [0.0], [1e-3], [1e-3])
    assert b.force([1e-7], [0.0], [1e-3], [1e-3]).shape == (1,)


def test_mindlin_sticks_as_a_spring_and_slides_at_coulombs_cap():
    t = dashpot.TangentialLaw("mindlin", mu=0.3).bind(**MCC)
    h = np.zeros((1, t.history_slots))
    n = [[0.0, 0.0, 1.0]]
    # a small slip: the spring force is −k_t v dt along the slip, below μ F_n
    f = t.force(1e-6, n, [[1e-3, 0.0, 0.0]], [10.0], [1e-5], [M_PAIR], [R_PAIR], h)
    assert f.shape == (1, 3) and f[0, 0] < 0.0 and f[0, 1] == 0.0 and abs(f[0, 0]) < 3.0
    # a large slip: capped at μ F_n = 3 N
    f = t.force(1.0, n, [[1.0, 0.0, 0.0]], [10.0], [1e-5], [M_PAIR], [R_PAIR], h)
    assert f[0, 0] == pytest.approx(-3.0, rel=1e-12)
    with pytest.raises(ValueError, match="shape"):
        t.force(1e-6, [0.0, 0.0, 1.0], [[1e-3, 0.0, 0.0]], [10.0], [1e-5], [M_PAIR], [R_PAIR], h)


def test_mcnamara_falcon_is_its_closed_form():
    r = dashpot.RestitutionLaw("mcnamara-falcon", r0=0.95, vy=0.3)
    v = np.array([0.01, 0.1, 0.3, 1.0, 3.0])
    expect = np.where(v <= 0.3, 1 - 0.05 * (v / 0.3) ** 0.2, 0.95 * (v / 0.3) ** -0.25)
    assert np.allclose(r.r(v), expect, rtol=1e-14)


def test_the_energy_outputs_of_hsd_are_its_elastic_potential_and_damping_power():
    b = dashpot.ContactLaw("hsd", eps=0.3).bind(**MCC)
    d = np.array([1e-6, 5e-6, 2e-5])
    rate = np.array([0.3, -0.2, 0.05])
    m, r = np.full(3, M_PAIR), np.full(3, R_PAIR)
    f, power, elastic, reach = b.force_energy(d, rate, m, r)
    assert np.array_equal(f, b.force(d, rate, m, r))
    f0 = b.force(d, np.zeros(3), m, r)
    # elastic (2/5) K δ^{5/2} = 0.4 F_Hertz δ; power: the damping force times the rate
    assert np.allclose(elastic, 0.4 * f0 * d, rtol=1e-12, atol=0.0)
    assert np.allclose(power, (f - f0) * rate, rtol=1e-9, atol=0.0)
    assert np.all(reach == 0.0)
    # an adhesive law reaches beyond touching
    jkr = dashpot.ContactLaw("jkr", w=0.1).bind(**MCC)
    _, _, _, reach = jkr.force_energy(d, rate, m, r, history=np.zeros((3, jkr.history_slots)))
    assert np.all(reach > 0.0)


def test_rolling_sds_is_a_spring_below_its_cap_and_slides_at_it():
    law = dashpot.RollingLaw("rolling-sds", k=1000.0, gamma=0.0, mu=0.1).bind(**MCC)
    assert law.history_slots == 6  # ξ, and the dashpot's share of the last force
    h = np.zeros((1, 6))
    n = [[0.0, 0.0, 1.0]]
    args = ([10.0], [1e-5], [M_PAIR], [R_PAIR])
    f, power, elastic = law.force(1e-6, n, [[1e-3, 0.0, 0.0]], *args, history=h, energy=True)
    # ξ = v dt, F = −k ξ, elastic k ξ²/2
    assert h[0, 0] == pytest.approx(1e-9, rel=1e-12) and f.shape == (1, 3)
    assert f[0, 0] == pytest.approx(-1e-6, rel=1e-12) and f[0, 1] == 0.0 and f[0, 2] == 0.0
    # all the work stored, none dissipated (to rounding of the work F·v = 1e-9 W)
    assert elastic[0] == pytest.approx(0.5 * 1000.0 * 1e-18, rel=1e-9) and abs(power[0]) < 1e-12 * 1e-9
    # a large roll: |F| capped at μ F_n = 1 N, the spring reset to the cap; the power is the work
    # of the force averaged over the step (−k ξ before it, the cap after) less what the spring
    # stored, then, sliding steadily, −F·v
    f, power, elastic = law.force(1.0, n, [[1.0, 0.0, 0.0]], *args, history=h, energy=True)
    assert f[0, 0] == pytest.approx(-1.0, rel=1e-12)
    assert h[0, 0] == pytest.approx(1e-3, rel=1e-12)
    assert elastic[0] == pytest.approx(5e-4, rel=1e-9)
    assert power[0] == pytest.approx(0.5 * (1.0 + 1e-6) - (5e-4 - 5e-16), rel=1e-9)
    f, power, elastic = law.force(1.0, n, [[1.0, 0.0, 0.0]], *args, history=h, energy=True)
    assert power[0] == pytest.approx(1.0, rel=1e-12) and elastic[0] == pytest.approx(5e-4, rel=1e-9)


def test_twisting_sds_is_a_torsion_spring_below_its_cap_and_slides_at_it():
    law = dashpot.TwistingLaw("twisting-sds", k=1e-3, gamma=0.0, mu=1e-4).bind(**MCC)
    h = np.zeros((1, law.history_slots))
    n = [[0.0, 0.0, 1.0]]
    args = ([10.0], [1e-5], [M_PAIR], [R_PAIR])
    t = law.torque(1e-6, n, [1.0], *args, history=h)
    assert t.shape == (1,) and t[0] == pytest.approx(-1e-9, rel=1e-12) and h[0, 0] == pytest.approx(1e-6)
    t, power, elastic = law.torque(10.0, n, [1.0], *args, history=h, energy=True)
    # capped at μ |F_n| = 1e-3 N·m: the torque averaged over the step's work less what the spring
    # stored (θ from 1e-6 to 1 rad), then, sliding steadily, |M ω|
    assert t[0] == pytest.approx(-1e-3, rel=1e-12)
    assert elastic[0] == pytest.approx(0.5 * 1e-3 * h[0, 0] ** 2, rel=1e-12)
    assert power[0] == pytest.approx(0.5 * (1e-3 + 1e-9) - (5e-4 - 5e-16) / 10.0, rel=1e-9)
    t, power, elastic = law.torque(10.0, n, [1.0], *args, history=h, energy=True)
    assert power[0] == pytest.approx(1e-3, rel=1e-12)


def test_every_kind_refuses_what_its_arrays_cannot_be():
    t = dashpot.TangentialLaw("mindlin", mu=0.3).bind(**MCC)
    h = np.zeros((2, t.history_slots))
    n = np.tile([0.0, 0.0, 1.0], (2, 1))
    with pytest.raises(ValueError, match=r"velocity has shape \(3, 3\)"):
        t.force(1e-6, n, np.zeros((3, 3)), [1.0, 1.0], [1e-5] * 2, [M_PAIR] * 2, [R_PAIR] * 2, h)
    with pytest.raises(ValueError, match="mass has 3 values, normal_force 2"):
        t.force(1e-6, n, n, [1.0, 1.0], [1e-5] * 2, [M_PAIR] * 3, [R_PAIR] * 2, h)
    with pytest.raises(ValueError, match="history has 3 values"):
        t.force(1e-6, n, n, [1.0, 1.0], [1e-5] * 2, [M_PAIR] * 2, [R_PAIR] * 2, np.zeros(3))
    with pytest.raises(ValueError, match="writeable, C-contiguous float64"):
        t.force(1e-6, n, n, [1.0, 1.0], [1e-5] * 2, [M_PAIR] * 2, [R_PAIR] * 2, np.zeros((2, 3), np.float32))
    with pytest.raises(ValueError, match="did you mean `rolling-sds`"):
        dashpot.RollingLaw("rolling-sdss").bind(**MCC)
    with pytest.raises(ValueError, match="'hsd' is a contact law"):
        dashpot.TwistingLaw("hsd").bind(**MCC)
    with pytest.raises(ValueError, match="mu"):
        dashpot.TwistingLaw("twisting-sds", mu=-1.0).bind(**MCC)
    w = dashpot.TwistingLaw("twisting-sds").bind(**MCC)
    with pytest.raises(ValueError, match="rate has 1 values, normal_force 2"):
        w.torque(1e-6, n, [1.0], [1.0, 1.0], [1e-5] * 2, [M_PAIR] * 2, [R_PAIR] * 2, np.zeros((2, 1)))


def test_jkr_tells_the_laws_of_its_contact_its_own_contact_radius():
    w, r = 0.1, R_PAIR
    e = MCC["young"] / (2.0 * (1.0 - MCC["poisson"] ** 2))
    delta_c = -0.75 * (np.pi**2 * w**2 * r / e**2) ** (1.0 / 3.0)
    jkr = dashpot.ContactLaw("jkr", w=w).bind(**MCC)
    m, rr = np.full(2, M_PAIR), np.full(2, r)
    h = np.zeros((2, jkr.history_slots))
    jkr.force_context([1e-9, 1e-9], [0.0, 0.0], m, rr, history=h)
    # past touching, before rupture: a solves δ = a²/R − √(2π w a/E) and stays positive
    d = np.array([0.5 * delta_c, 0.9 * delta_c])
    f, x = jkr.force_context(d, [0.0, 0.0], m, rr, history=h)
    a = x[:, 0]
    assert x.shape == (2, 3) and np.all(a > 0.0) and np.all(x[:, 1] > 0.0) and np.all(x[:, 2] == 0.0)
    assert np.allclose(a * a / r - np.sqrt(2 * np.pi * w * a / e), d, rtol=0.0, atol=1e-9 * abs(delta_c))
    # a law that reports no context of its own gives the default: √(R δ), max(F, 0), 0
    hsd = dashpot.ContactLaw("hsd", eps=0.5).bind(**MCC)
    dd = np.array([1e-6, -1e-7])
    f, x = hsd.force_context(dd, [0.1, 0.1], m, rr)
    assert np.array_equal(x, np.column_stack([np.sqrt(rr * np.maximum(dd, 0.0)), np.maximum(f, 0.0), np.zeros(2)]))
    # mindlin does not read the context: giving it one changes nothing
    t = dashpot.TangentialLaw("mindlin", mu=0.3).bind(**MCC)
    assert not t.reads_context and not jkr.reads_context
    n, v = [[0.0, 0.0, 1.0]] * 2, [[1e-3, 0.0, 0.0]] * 2
    h1, h2 = np.zeros((2, t.history_slots)), np.zeros((2, t.history_slots))
    f1 = t.force(1e-6, n, v, [10.0, 5.0], [1e-5, 1e-5], m, rr, h1)
    f2 = t.force(1e-6, n, v, [10.0, 5.0], [1e-5, 1e-5], m, rr, h2, context=x)
    assert np.array_equal(f1, f2) and np.array_equal(h1, h2)
    with pytest.raises(ValueError, match="context has shape"):
        t.force(1e-6, n, v, [10.0, 5.0], [1e-5, 1e-5], m, rr, h1, context=np.zeros((1, 3)))
    bad = x.copy()
    bad[1, 0] = np.nan
    with pytest.raises(ValueError, match=r"input context\[1\]"):
        t.force(1e-6, n, v, [10.0, 5.0], [1e-5, 1e-5], m, rr, h1, context=bad)
