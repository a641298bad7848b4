"""sweep, bed and calibrate against the CLI's output to the bit (the same grids, the same
bed), and what each refuses."""

import csv
import io
import math

import numpy as np
import pytest

import dashpot
from conftest import cli, cli_text, sets


def read_csv(path):
    """A CSV the CLI wrote, its `#` provenance lines skipped: the header and the rows."""
    with open(path) as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    return rows[0], rows[1:]


def test_sweep_is_the_clis_csv_to_the_bit(tmp_path):
    out = tmp_path / "sweep.csv"
    cli_text("sweep", "--law", "hsd", "--set", "eps=0.5", "--v0", "1e-3:10:7", "--vary", "eps=0.3,0.6,0.9",
             "--rtol", "1e-9", "--out", out)
    header, rows = read_csv(out)
    s = dashpot.sweep("hsd", v0="1e-3:10:7", vary={"eps": [0.3, 0.6, 0.9]}, rtol=1e-9, eps=0.5)
    assert header == ["law", "eps", "v0_m_per_s", "end", "restitution", "contact_time_s", "max_overlap_m",
                      "max_overlap_time_s"]
    assert len(rows) == 21 and s["v0"].shape == (21,)
    cols = {"eps": "eps", "v0_m_per_s": "v0", "restitution": "restitution", "contact_time_s": "contact_time",
            "max_overlap_m": "max_overlap", "max_overlap_time_s": "max_overlap_time"}
    for k, row in enumerate(rows):
        assert row[0] == s["law"] and row[3] == s["end"] == "overlap"
        for j, name in enumerate(header):
            if name in cols:
                assert float(row[j]) == s[cols[name]][k], (k, name, row[j], s[cols[name]][k])
    # HSD realizes its eps at every speed (δ back to 0): the physics, not only the bits
    assert np.allclose(s["restitution"], s["eps"], atol=1e-7)
    assert s["provenance"]["law"] == "hsd"


def test_sweep_takes_arrays_and_keeps_the_order_of_the_cli():
    v = np.array([0.05, 0.5, 5.0])
    s = dashpot.sweep("kuwabara-kono", v0=v, vary={"A": "1e-6,4e-6"}, end="force")
    assert list(s["A"]) == [1e-6] * 3 + [4e-6] * 3 and list(s["v0"]) == list(v) * 2
    # Kuwabara–Kono: restitution falls with the impact speed and with A
    e = s["restitution"].reshape(2, 3)
    assert np.all(np.diff(e, axis=1) < 0) and np.all(e[1] < e[0])


def test_sweep_refuses_bad_grids_and_speeds():
    with pytest.raises(ValueError, match="v0 = -1"):
        dashpot.sweep("hsd", v0=[1.0, -1.0])
    with pytest.raises(ValueError, match="'x:1:3'"):
        dashpot.sweep("hsd", v0="x:1:3")
    with pytest.raises(ValueError, match="epsx"):
        dashpot.sweep("hsd", v0=[1.0], vary={"epsx": [0.5]})


BED = dict(layers=0.5, freq=20.0, cycles=2.0, transient=1.0, seed=3)
# what measures the machine, not the bed
WALL_KEYS = {"wall_seconds", "events_per_second", "collisions_per_second", "wall_per_simulated_second"}


def same_json(a, b, path=""):
    """a == b to the bit, but for the keys that measure wall-clock time."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and set(a) == set(b), (path, set(a) ^ set(b))
        for k in a:
            if k not in WALL_KEYS:
                same_json(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            same_json(x, y, f"{path}[{i}]")
    else:
        assert a == b and type(a) is type(b), (path, a, b)


def test_bed_is_the_clis_json_to_the_bit():
    ref = cli("bed", "--restitution", "mcnamara-falcon", "--layers", "0.5", "--freq", "20", "--cycles", "2",
              "--transient", "1", "--seed", "3", "--json")
    got = dashpot.bed(restitution="mcnamara-falcon", **BED)
    same_json(ref, got)
    assert got["collisions"] > 1000 and got["pressure"] > 0.0
    # the mean impulse per lid collision times their rate over the width is the pressure
    assert got["pressure"] == pytest.approx(got["lid_collision_rate"] * got["mean_impulse"] / 0.2, rel=1e-12)


def test_a_dem_bed_is_the_clis_json_to_the_bit():
    args = ["--law", "hsd", "--set", "eps=0.8", "--young", "1e7", "--layers", "0.2", "--freq", "20",
            "--cycles", "0.5", "--transient", "0", "--gravity", "9.8"]
    ref = cli("bed", "--engine", "dem", *args, "--json")
    got = dashpot.bed(law="hsd", params={"eps": 0.8}, young=1e7, layers=0.2, freq=20, cycles=0.5, transient=0,
                      gravity=9.8)
    same_json(ref, got)
    assert got["engine"] == "dem" and got["steps"] > 0


def test_bed_refusals_are_value_errors_naming_the_value():
    with pytest.raises(ValueError, match="--cycles = -1"):
        dashpot.bed(restitution="constant", layers=1, freq=20, cycles=-1)
    with pytest.raises(ValueError, match="mcnamara-falconn"):
        dashpot.bed(restitution="mcnamara-falconn", layers=1, freq=20, cycles=1)
    with pytest.raises(ValueError, match="--tc 0.001"):
        dashpot.bed(law="hsd", layers=1, freq=20, cycles=1, tc=1e-3)


def test_calibrate_is_the_clis_and_hits_its_target():
    ref = cli("calibrate", "--law", "kuwabara-kono", "--restitution", "0.8", "--v0", "0.5", "--json")
    c = dashpot.calibrate("kuwabara-kono", 0.8, v0=0.5)
    same_json(ref, c)
    assert abs(c["restitution"] - 0.8) < 1e-8
    with pytest.raises(ValueError, match="1.5"):
        dashpot.calibrate("hsd", 1.5)


@pytest.mark.parametrize("law,params,v0", [("hsd", {"eps": 0.54}, 1.0), ("kuwabara-kono", {"A": 2e-6}, 0.5),
                                           ("jkr", {"w": 0.1}, 1e-3), ("thornton", {"py": 1e7}, 2.0)])
def test_collide_is_the_clis_json_to_the_bit(law, params, v0):
    ref = cli("collide", "--law", law, *sets(params), "--v0", repr(v0), "--json")
    c = dashpot.collide(law, v0=v0, **params)
    ref["pair"].pop("partner")
    c = {k: v for k, v in c.items()}
    same_json(ref, c)


def test_collide_gives_each_new_parameter_value_its_own_provenance():
    # a calibration loop: the same law with a new value at each call (the provenance's other
    # parts are built once per law and given names), defaults and derived parameters beside
    # it, a value met again (its law is reused); a result's params are its own
    for law, name, values in [("hsd", "eps", (0.3, 0.31, 0.3)), ("thornton", "py", (1e7, 2e7))]:
        for x in values:
            ref = cli("collide", "--law", law, "--set", f"{name}={x!r}", "--v0", "1.0", "--json")
            c = dashpot.collide(law, v0=1.0, **{name: x})
            ref["pair"].pop("partner")
            same_json(ref, dict(c))
            assert c["params"][name] == x and c["provenance"]["params"][name] == x
            c["params"][name] = c["provenance"]["params"][name] = -1.0  # each result's own


@pytest.mark.parametrize("law,params", [("hsd", {"eps": 0.3}), ("lsd", {"eps": 0.7}), ("kuwabara-kono", {"A": 2e-6}),
                                        ("jkr", {"w": 0.5, "eps": 0.8}), ("thornton", {"py": 1e7})])
def test_a_curve_is_its_collisions_to_the_bit(law, params):
    # 37 speeds: more than the collisions run in lockstep at once; both end criteria
    v0 = np.logspace(-3, 1, 37)
    for end in ("overlap", "force"):
        c = dashpot.collide(law, v0=v0, end=end, rtol=1e-9, **params)
        assert c["v0"].dtype == np.float64 and np.array_equal(c["v0"], v0)
        for i, v in enumerate(v0):
            one = dashpot.collide(law, v0=float(v), end=end, rtol=1e-9, **params)
            for key in ("restitution", "contact_time", "max_overlap", "max_overlap_time"):
                assert c[key][i].tobytes() == np.float64(one[key]).tobytes(), (key, v)
            for key in ("steps", "force_evals", "stuck"):
                assert c[key][i] == one[key], (key, v)
            tp = one["tensile_peak"]
            assert (math.isnan(c["tensile_peak"][i]) if tp is None else c["tensile_peak"][i] == tp)
        for key in ("law", "end", "rtol", "pair", "params", "provenance"):
            assert c[key] == one[key], key


def test_a_curve_realizes_hsds_epsilon_and_takes_any_real_array():
    # HSD's ε does not depend on v0 (Antypov & Elliott); ints and float32 are converted
    c = dashpot.collide("hsd", v0=np.array([1, 2, 5]), eps=0.25, rtol=1e-10)
    assert np.all(np.abs(c["restitution"] - 0.25) < 1e-9)
    c32 = dashpot.collide("hsd", v0=np.array([1, 2, 5], dtype=np.float32), eps=0.25, rtol=1e-10)
    assert np.array_equal(c32["restitution"], c["restitution"])
    assert dashpot.collide("hsd", v0=np.array([]), eps=0.25)["restitution"].shape == (0,)


def test_a_curve_refuses_what_one_collision_refuses():
    with pytest.raises(ValueError, match=r"v0\[2\].*NaN"):
        dashpot.collide("hsd", v0=[1.0, 2.0, float("nan")])
    with pytest.raises(ValueError, match=r"v0\[0\].*-1"):
        dashpot.collide("hsd", v0=[-1.0])
    with pytest.raises(ValueError, match=r"shape \(2, 2\)"):
        dashpot.collide("hsd", v0=np.ones((2, 2)))
    with pytest.raises(ValueError, match="dtype"):
        dashpot.collide("hsd", v0=np.array(["1", "2"]))
    with pytest.raises(ValueError, match="record"):
        dashpot.collide("hsd", v0=[1.0, 2.0], record=True)
    with pytest.raises(ValueError, match="eps"):
        dashpot.collide("hsd", v0=[1.0, 2.0], eps=2.0)
    with pytest.raises(ValueError, match="rtol"):
        dashpot.collide("hsd", v0=[1.0, 2.0], rtol=0.5)
