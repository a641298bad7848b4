"""Calibration round trips in Python: collide ends a contact by the law's own criterion (so a
calibrated law gives back its target), calibrate(data=...) fits a measured curve by least squares
as the CLI's --data does, and a fit that misses its target raises."""

import numpy as np
import pytest

import dashpot
from conftest import cli


def test_a_calibrated_law_reproduces_its_target_in_collide():
    c = dashpot.calibrate("kuwabara-kono", 0.8, v0=1.0)
    assert c["end"] == "force"
    r = dashpot.collide("kuwabara-kono", 1.0, A=c["params"]["A"])
    assert r["end"] == "force"
    assert abs(r["restitution"] - 0.8) < 1e-9
    # and the curve form uses the same criterion
    curve = dashpot.collide("kuwabara-kono", np.array([1.0, 2.0]), A=c["params"]["A"])
    assert curve["restitution"][0] == r["restitution"]
    # end= still overrides
    assert dashpot.collide("kuwabara-kono", 1.0, end="overlap", A=c["params"]["A"])["restitution"] < 0.7999
    s = dashpot.sweep("kuwabara-kono", v0=[1.0], A=c["params"]["A"])
    assert s["end"] == "force" and abs(s["restitution"][0] - 0.8) < 1e-9


def _kk_curve(a):
    v0 = np.logspace(-2, 1, 10)
    return np.column_stack([v0, dashpot.collide("kuwabara-kono", v0, A=a)["restitution"]])


def test_a_ten_point_curve_gives_back_a_to_1e6_from_an_array_and_from_a_file(tmp_path):
    data = _kk_curve(2e-6)
    f = dashpot.calibrate("kuwabara-kono", data=data)
    assert abs(f["params"]["A"] / 2e-6 - 1) < 1e-6
    assert f["fitted"][0]["name"] == "A"
    assert f["residuals"].shape == (10,) and np.all(np.abs(f["residuals"]) < 1e-9)
    assert f["rms"] < 1e-9
    path = tmp_path / "kk.csv"
    path.write_text("v0,e\n" + "".join(f"{float(v)!r},{float(e)!r}\n" for v, e in data))
    g = dashpot.calibrate("kuwabara-kono", data=path)
    assert g["params"] == f["params"]
    # the CLI's --data fit, to the bit
    ref = cli("calibrate", "--law", "kuwabara-kono", "--data", str(path), "--out", str(tmp_path / "fig"), "--json")
    assert ref["params"] == g["params"] and ref["rms"] == g["rms"]


def test_bad_data_and_missed_targets_raise():
    with pytest.raises(ValueError, match=r"e = 1.5"):
        dashpot.calibrate("kuwabara-kono", data=[[1.0, 1.5], [2.0, 0.5]])
    with pytest.raises(ValueError, match=r"shape"):
        dashpot.calibrate("kuwabara-kono", data=[1.0, 0.5])
    with pytest.raises(ValueError, match=r"not both"):
        dashpot.calibrate("kuwabara-kono", 0.5, data=[[1.0, 0.5]])
    with pytest.raises(ValueError, match=r"restitution 0.01: it jumps from .* misses it by"):
        dashpot.calibrate("dmt", 0.01, fit="w")
