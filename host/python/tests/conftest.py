"""Points the package at the plugins and the CLI of the checkout it lives in (unless the
environment already does): `target/debug` of the repository root; and the helpers the tests
share: the CLI (`cli`, `cli_text`), the MCC pair."""

import json
import math
import os
import pathlib
import subprocess

ROOT = pathlib.Path(__file__).resolve().parents[3]
os.environ.setdefault("DASHPOT_PLUGIN_PATH", str(ROOT / "target" / "debug"))
os.environ.setdefault("DASHPOT_BIN", str(ROOT / "target" / "debug" / "dashpot"))

MCC = dict(young=6e9, poisson=0.3)
# the CLI's default pair: two 1 cm MCC spheres (ρ = 1500 kg/m³)
M_PAIR = 1500.0 * math.pi / 6.0 * 0.01**3 / 2.0
R_PAIR = 0.0025


def cli_text(*args):
    """Runs the CLI (this build's binary and plugins); its stdout, or the test fails."""
    out = subprocess.run([os.environ["DASHPOT_BIN"], *map(str, args)], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return out.stdout


def cli(*args):
    """The CLI's JSON output."""
    return json.loads(cli_text(*args))


def sets(params, flag="--set"):
    """NAME=VALUE arguments, values as Python writes them (the shortest round trip)."""
    return sum(([flag, f"{k}={v!r}"] for k, v in params.items()), [])


def third_party_plugin():
    """The third-party fixture `hooke-limited` (tests/fixtures/third-party, its own workspace, as
    an outside author builds it): `DASHPOT_THIRD_PARTY_PLUGIN` if the runner built it (cargo test
    does), else built here into target/external as the Rust tests build it."""
    given = os.environ.get("DASHPOT_THIRD_PARTY_PLUGIN")
    if given:
        return pathlib.Path(given)
    target = ROOT / "target" / "external"
    subprocess.run(["cargo", "build", "--quiet", "--manifest-path", str(ROOT / "tests/fixtures/third-party/Cargo.toml"),
                    "-p", "dashpot-fixture-limited", "--target-dir", str(target)], check=True)
    return target / "debug" / "libdashpot_fixture_limited.so"
