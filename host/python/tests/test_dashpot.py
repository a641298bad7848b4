"""The Python package against the CLI and against physics: the same plugins give the same bits
through numpy as through `dashpot eval` and `dashpot collide`, batches are invariant under
splitting, and every refusal is the right exception naming the value.

Run with the plugins and the CLI of a built checkout: `DASHPOT_PLUGIN_PATH=target/debug` and
`DASHPOT_BIN=target/debug/dashpot` (conftest.py sets both from the repository root)."""

import json
import math
import os
import subprocess

import numpy as np
import pytest

import dashpot

MCC = dict(young=6e9, poisson=0.3)
# the CLI's default pair: two 1 cm MCC spheres (ρ = 1500 kg/m³)
M_PAIR = 1500.0 * math.pi / 6.0 * 0.01**3 / 2.0
R_PAIR = 0.0025


def cli(*args):
    out = subprocess.run([os.environ["DASHPOT_BIN"], *args], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def test_laws_lists_every_shipped_law_with_its_schema():
    names = {l["name"]: l for l in dashpot.laws()}
    for n in ["lsd", "hsd", "kuwabara-kono", "thornton", "walton-braun", "jkr", "dmt", "mindlin"]:
        assert n in names, n
    assert names["hsd"]["kind"] == "contact"
    assert [p["name"] for p in names["hsd"]["params"]] == ["eps"]


@pytest.mark.parametrize("law,params", [("hsd", {"eps": 0.3}), ("lsd", {"eps": 0.5}),
                                        ("kuwabara-kono", {"A": 2e-6}), ("dmt", {"w": 0.1})])
def test_forces_are_the_clis_to_the_bit(law, params):
    b = dashpot.ContactLaw(law, **params).bind(**MCC)
    sets = sum((["--set", f"{k}={v}"] for k, v in params.items()), [])
    for delta, rate in [(1e-5, 0.1), (3e-6, -0.4), (2.5e-5, 1.3)]:
        ref = cli("eval", "--law", law, *sets, "--delta", repr(delta), "--rate", repr(rate), "--json")
        f = b.force(np.array([delta]), np.array([rate]), np.array([M_PAIR]), np.array([R_PAIR]))
        assert f[0] == ref["force"], (law, delta, rate, f[0], ref["force"])


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


@pytest.mark.parametrize("law,params,v0", [("hsd", {"eps": 0.54}, 1.0), ("kuwabara-kono", {"A": 2e-6}, 0.5),
                                           ("jkr", {"w": 0.1}, 1e-3)])
def test_collide_is_the_clis_to_the_bit(law, params, v0):
    sets = sum((["--set", f"{k}={v}"] for k, v in params.items()), [])
    ref = cli("collide", "--law", law, *sets, "--v0", repr(v0), "--json")
    c = dashpot.collide(law, v0=v0, **params)
    for key in ["restitution", "contact_time", "max_overlap", "max_overlap_time", "steps", "stuck"]:
        assert c[key] == ref[key], (key, c[key], ref[key])
    assert c["provenance"]["law"] == law


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
    ref = cli("eval", "--law", "mcnamara-falcon", "--set", "r0=0.95", "--set", "vy=0.3", "--speed", "1", "--json")
    assert r.r([1.0])[0] == ref["restitution"]


def test_calibrate_is_the_clis_and_hits_its_target():
    ref = cli("calibrate", "--law", "kuwabara-kono", "--restitution", "0.8", "--v0", "0.5", "--json")
    c = dashpot.calibrate("kuwabara-kono", 0.8, v0=0.5)
    assert c["params"] == ref["params"] and c["restitution"] == ref["restitution"]
    assert abs(c["restitution"] - 0.8) < 1e-8
    with pytest.raises(ValueError, match="1.5"):
        dashpot.calibrate("hsd", 1.5)
