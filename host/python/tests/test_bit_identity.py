"""Forces for 10⁶ numpy contacts through the package, for every shipped contact law, are the
bits of the Rust batch call on the same contacts and of one call per contact (what `dashpot
eval` makes), and at sampled contacts the bits the CLI's `eval --json` prints; the same for the
restitution laws' r(v)."""

import numpy as np
import pytest

import dashpot
from conftest import MCC, cli, sets

N = 1_000_000

CONTACT_LAWS = [
    ("lsd", {"eps": 0.5}),
    ("hsd", {"eps": 0.3}),
    ("kuwabara-kono", {"A": 2e-6}),
    ("thornton", {"py": 1e8}),
    ("walton-braun", {"k1": 1e6, "k2": 2e6}),
    ("jkr", {"w": 0.1}),
    ("dmt", {"w": 0.1}),
]
# LAMMPS's sub-models (plugin dashpot_granular): every normal x damping law LAMMPS accepts
GRAN_DAMP = {"velocity": 0.5, "mass-velocity": 100.0, "viscoelastic": 1e5, "tsuji": 0.5, "coeff-restitution": 0.5}
GRAN_NORMAL = {"hooke": {"k": 1e6}, "hertz": {"k": 1e9}, "hertz-material": {}, "dmt": {"cohesion": 0.1},
               "jkr": {"cohesion": 0.1}}
CONTACT_LAWS += [(f"gran-{n}-{d}", {**p, "damp": v}) for n, p in GRAN_NORMAL.items() for d, v in GRAN_DAMP.items()
                 if not (n in ("dmt", "jkr") and d in ("tsuji", "coeff-restitution"))]


def test_every_shipped_contact_law_is_tested_here():
    shipped = {l["name"] for l in dashpot.laws()
               if l["kind"] == "contact" and not l["plugin"]["name"].startswith("dashpot-fixture-")}
    assert shipped == {n for n, _ in CONTACT_LAWS}


@pytest.fixture(scope="module")
def contacts():
    """10⁶ contacts in and around contact (some separated, some unloading), and at four places
    the pair of the CLI's `eval` (two spheres of diameter d, ρ = 1500 kg/m³)."""
    rng = np.random.default_rng(2026)
    delta = rng.uniform(-2e-6, 2e-5, N)
    rate = rng.uniform(-1.0, 1.0, N)
    mass = rng.uniform(1e-5, 1e-3, N)
    radius = rng.uniform(1e-3, 5e-3, N)
    return delta, rate, mass, radius


EVAL_POINTS = [(0.01, 1e-5, 0.1), (0.01, 3e-6, -0.4), (0.004, 2.5e-6, 1.3), (0.02, 1e-7, 0.0)]


@pytest.mark.parametrize("law,params", CONTACT_LAWS, ids=[n for n, _ in CONTACT_LAWS])
def test_a_million_contacts_are_the_rust_batch_and_the_clis_eval_to_the_bit(law, params, contacts):
    delta, rate, mass, radius = (x.copy() for x in contacts)
    # the CLI's eval at a few contacts, planted into the batch
    expect = {}
    for k, (d, dl, rt) in enumerate(EVAL_POINTS):
        ref = cli("eval", "--law", law, *sets(params), "--diameter", repr(d), "--delta", repr(dl),
                  "--rate", repr(rt), "--json")
        i = 1000 * k + 17
        delta[i], rate[i], mass[i], radius[i] = dl, rt, ref["pair"]["mass"], ref["pair"]["radius"]
        expect[i] = ref["force"]
    b = dashpot.ContactLaw(law, **params).bind(**MCC)
    h = np.zeros((N, b.history_slots)) if b.history_slots else None
    f = b.force(delta, rate, mass, radius, history=h)
    batch, one_by_one = b._inner._reference((delta, rate, mass, radius))
    assert f.dtype == np.float64 and f.shape == (N,)
    assert np.array_equal(f, batch), f"{law}: Python and the Rust batch differ"
    assert np.array_equal(f, one_by_one), f"{law}: the batch and one call per contact differ"
    for i, force in expect.items():
        assert f[i] == force, (law, i, f[i], force)
    assert np.count_nonzero(f) > N // 2


@pytest.mark.parametrize("law,params", [("mcnamara-falcon", {"r0": 0.95, "vy": 0.3}), ("constant", {"r": 0.7})])
def test_restitution_laws_are_the_clis_eval_to_the_bit(law, params):
    speeds = np.random.default_rng(5).uniform(0.0, 5.0, N)
    at = [0.0, 0.01, 0.3, 1.0, 4.2]
    speeds[: len(at)] = at
    r = dashpot.RestitutionLaw(law, **params).r(speeds)
    assert r.shape == (N,) and np.all((r > 0) & (r <= 1))
    for i, v in enumerate(at):
        ref = cli("eval", "--law", law, *sets(params), "--speed", repr(v), "--json")
        assert r[i] == ref["restitution"], (law, v)
