"""Plugins: a third-party law (built as an outside author builds it) loads from Python and acts
as its formula says, its panic is an exception Python survives; the built-in laws come with the
installed package when it was built by `pip install ./host/python`."""

import json
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import dashpot
from conftest import M_PAIR, MCC, R_PAIR, third_party_plugin


def test_a_third_party_law_loads_from_python_and_is_its_formula():
    path = third_party_plugin()
    dashpot.load_plugin(path)
    law = {l["name"]: l for l in dashpot.laws()}["hooke-limited"]
    assert law["kind"] == "contact" and pathlib.Path(law["plugin"]["file"]).name == path.name
    b = dashpot.ContactLaw("hooke-limited", k=2e6, c=30.0).bind(**MCC)
    d, r = np.array([0.0, 1e-4, 5e-4, -1e-5]), np.array([0.1, -0.2, 0.0, 1.0])
    f = b.force(d, r, np.full(4, M_PAIR), np.full(4, R_PAIR))
    assert np.array_equal(f, np.where(d < 0.0, 0.0, 2e6 * d + 30.0 * r))
    # beyond its 1 mm the law panics: an exception, and Python carries on
    with pytest.raises(RuntimeError, match="panicked.*beyond what this law supports"):
        b.force([2e-3], [0.0], [M_PAIR], [R_PAIR])
    assert b.force([1e-4], [0.0], [M_PAIR], [R_PAIR])[0] == 2e6 * 1e-4
    # the collision driver runs it, and the provenance names its file
    c = dashpot.collide("hooke-limited", v0=0.1, k=2e6, c=0.0)
    assert c["restitution"] == pytest.approx(1.0, abs=1e-8)
    assert c["provenance"]["plugin"]["file"] == str(path)
    with pytest.raises(ValueError, match="did you mean `k`"):
        dashpot.ContactLaw("hooke-limited", kk=1.0).bind(**MCC)


def test_a_missing_plugin_file_is_a_plugin_error(tmp_path):
    with pytest.raises(dashpot.PluginError, match="nothing.so"):
        dashpot.load_plugin(tmp_path / "nothing.so")


BUILT_IN = {"lsd", "hsd", "kuwabara-kono", "thornton", "walton-braun", "jkr", "dmt", "mcnamara-falcon",
            "constant", "mindlin", "linear-history", "rolling-sds", "rolling-epsd", "twisting-sds",
            "twisting-marshall"}


def test_the_installed_package_carries_the_built_in_laws():
    plugins = pathlib.Path(dashpot.__file__).parent / "plugins"
    if not plugins.is_dir():
        pytest.skip(f"this installation has no {plugins} (a development install: maturin develop); "
                    "`pip install ./host/python` puts the built-in plugins there")
    code = ("import dashpot, json; print(json.dumps([[l['name'], l['plugin']['file']] for l in dashpot.laws()]));"
            "print(dashpot.collide('hsd', v0=1.0, eps=0.54)['restitution'])")
    env = {k: v for k, v in os.environ.items() if k != "DASHPOT_PLUGIN_PATH"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True).stdout
    listed, e = out.splitlines()
    names = {n: pathlib.Path(f) for n, f in json.loads(listed)}
    assert BUILT_IN <= set(names), BUILT_IN - set(names)
    assert all(names[n].parent == plugins for n in BUILT_IN)
    assert abs(float(e) - 0.54) < 1e-8
