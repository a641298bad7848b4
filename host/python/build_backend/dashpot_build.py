"""The package's PEP 517 build backend: maturin's, after one step of its own.

``pip install ./host/python`` builds a wheel that carries dashpot's built-in laws: before
maturin builds the extension module, this backend builds the plugin crates of the workspace
(``plugins/*``, the cdylib crates the CLI ships beside itself) with cargo in release and copies
their libraries into ``python/dashpot/plugins``, where the package looks for its own laws (after
``DASHPOT_PLUGIN_PATH``). Rust is needed anyway, for the extension; maturin itself comes from
PyPI (``build-system.requires``). Set ``DASHPOT_WHEEL_PLUGINS=0`` to build a wheel without them
(the laws then come from ``DASHPOT_PLUGIN_PATH`` only).

Every hook not defined here is maturin's."""

from __future__ import annotations

import json
import os
import pathlib
import shutil
import subprocess
import sys

from maturin import *  # noqa: F401,F403  (the PEP 517 hooks this module does not override)
import maturin as _maturin

PROJECT = pathlib.Path(__file__).resolve().parent.parent  # host/python
WORKSPACE = PROJECT.parent.parent  # the repository root
STAGE = PROJECT / "python" / "dashpot" / "plugins"


def _say(msg: str) -> None:
    print(f"dashpot build: {msg}", file=sys.stderr, flush=True)


def _plugin_packages(cargo: str) -> list:
    """The workspace's plugin crates: cdylib packages under plugins/."""
    meta = json.loads(subprocess.run(
        [cargo, "metadata", "--format-version", "1", "--no-deps", "--manifest-path", str(WORKSPACE / "Cargo.toml")],
        check=True, capture_output=True, text=True).stdout)
    plugins = WORKSPACE / "plugins"
    return sorted(p["name"] for p in meta["packages"]
                  if pathlib.Path(p["manifest_path"]).resolve().is_relative_to(plugins)
                  and any("cdylib" in t["kind"] for t in p["targets"]))


def stage_plugins() -> None:
    """Builds the built-in plugins (release) and copies them into python/dashpot/plugins."""
    if os.environ.get("DASHPOT_WHEEL_PLUGINS", "1") == "0":
        _say("DASHPOT_WHEEL_PLUGINS=0: the wheel carries no plugins")
        shutil.rmtree(STAGE, ignore_errors=True)
        return
    if not (WORKSPACE / "plugins").is_dir():
        raise RuntimeError(f"dashpot build: no plugins/ beside {PROJECT}: build the wheel from a dashpot "
                           "checkout (pip install ./host/python), or set DASHPOT_WHEEL_PLUGINS=0")
    cargo = os.environ.get("CARGO", "cargo")
    packages = _plugin_packages(cargo)
    _say(f"building the built-in plugins: {', '.join(packages)}")
    cmd = [cargo, "build", "--release", "--message-format=json-render-diagnostics",
           "--manifest-path", str(WORKSPACE / "Cargo.toml")]
    for p in packages:
        cmd += ["-p", p]
    run = subprocess.run(cmd, check=True, stdout=subprocess.PIPE, text=True)
    libs = []
    for line in run.stdout.splitlines():
        msg = json.loads(line) if line.startswith("{") else {}
        if msg.get("reason") == "compiler-artifact" and "cdylib" in msg["target"]["kind"] \
                and msg["package_id"] and msg["target"]["name"].replace("_", "-") in packages:
            libs += [f for f in msg["filenames"] if f.endswith((".so", ".dylib", ".dll"))]
    if len(libs) != len(packages):
        raise RuntimeError(f"dashpot build: cargo built {len(libs)} plugin libraries for {len(packages)} crates")
    shutil.rmtree(STAGE, ignore_errors=True)
    STAGE.mkdir(parents=True)
    for f in libs:
        shutil.copy2(f, STAGE / pathlib.Path(f).name)
    _say(f"{len(libs)} plugins staged in {STAGE}")


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    stage_plugins()
    return _maturin.build_wheel(wheel_directory, config_settings, metadata_directory)


def build_editable(wheel_directory, config_settings=None, metadata_directory=None):
    stage_plugins()
    return _maturin.build_editable(wheel_directory, config_settings, metadata_directory)
