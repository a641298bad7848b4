"""The examples of examples/python run and exit 0 (the fitting example where SciPy and
matplotlib are installed)."""

import importlib.util
import os
import subprocess
import sys

import pytest

from conftest import ROOT

EXAMPLES = ROOT / "examples" / "python"


@pytest.mark.parametrize("name,needs", [("forces_for_contacts.py", []), ("run_scene.py", []),
                                        ("fit_restitution.py", ["scipy", "matplotlib"])])
def test_the_example_runs(name, needs, tmp_path):
    missing = [m for m in needs if importlib.util.find_spec(m) is None]
    if missing:
        pytest.skip(f"{name} needs {', '.join(missing)}, not installed in this venv")
    env = dict(os.environ, MPLBACKEND="Agg")
    out = subprocess.run([sys.executable, str(EXAMPLES / name)], capture_output=True, text=True, cwd=tmp_path,
                         env=env, timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip(), "the example printed nothing"
