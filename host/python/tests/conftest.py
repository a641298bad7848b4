"""Points the package at the plugins and the CLI of the checkout it lives in (unless the
environment already does): `target/debug` of the repository root."""

import os
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[3]
os.environ.setdefault("DASHPOT_PLUGIN_PATH", str(ROOT / "target" / "debug"))
os.environ.setdefault("DASHPOT_BIN", str(ROOT / "target" / "debug" / "dashpot"))
