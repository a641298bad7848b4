#!/usr/bin/env python3
"""The rotating drum of examples/dem/drum.toml in dashpot and in LAMMPS (examples/dem/lammps/in.drum):
the dynamic angle of repose of each, and dashpot's energy books.

    python3 examples/dem/drum_compare.py [--duration 8] [--since 4] [--frames 40] [--work DIR]
        [--dashpot PATH] [--plugin-dir DIR] [--lmp PATH] [--skip-lammps]

dashpot runs the scene with --out (a frame every duration/frames); LAMMPS starts from the same
spheres (dashpot's state at t = 0, written as a LAMMPS data file), with the same step, skin and
laws, and dumps the positions at the same times. The angle of each frame, two ways:

- from the centre of mass of the spheres' cross-section: the bed of a half-full drum is a
  circular segment, whose centroid lies on the perpendicular to its free surface through the
  drum's axis, so the surface's angle to the horizontal is the angle of that centroid from the
  vertical (exact for a flat surface at any fill);
- from a line fitted to the free surface: in bins of x across the middle 70 % of the drum's
  diameter, the highest sphere top per bin, fitted by least squares.

Each is averaged over the frames from --since on (the bed has left its start and flows steadily);
the spread is the frames' standard deviation. Needs numpy; LAMMPS from $DASHPOT_LAMMPS_VENV/bin/lmp
(or --lmp).
"""

import argparse
import json
import math
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
R = 0.04  # the drum's radius (m), as in drum.toml


def scene_text(duration: float, frames: int) -> str:
    text = (HERE / "drum.toml").read_text()
    text = re.sub(r"^duration = .*$", f"duration = {duration!r}", text, count=1, flags=re.M)
    return re.sub(r"^snapshots = .*$", f"snapshots = {frames}", text, count=1, flags=re.M)


def dashpot(args, *extra):
    cmd = [args.dashpot]
    if args.plugin_dir:
        cmd += ["--no-default-plugins", "--plugin-dir", args.plugin_dir]
    return subprocess.run(cmd + ["dem", *extra], check=True, capture_output=True, text=True)


def frames_xyz(path: Path):
    """(time, positions (N, 3)) of each frame of an extended XYZ trajectory."""
    out = []
    lines = path.read_text().splitlines()
    k = 0
    while k < len(lines):
        n = int(lines[k])
        t = float(re.search(r"Time=(\S+)", lines[k + 1]).group(1))
        x = np.array([[float(v) for v in line.split()[1:4]] for line in lines[k + 2:k + 2 + n]])
        out.append((t, x))
        k += 2 + n
    return out


def frames_dump(path: Path, dt: float):
    """(time, positions (N, 3)) of each frame of a LAMMPS custom dump (id x y z radius)."""
    out = []
    lines = path.read_text().splitlines()
    k = 0
    while k < len(lines):
        step = int(lines[k + 1])
        n = int(lines[k + 3])
        rows = np.array([[float(v) for v in line.split()] for line in lines[k + 9:k + 9 + n]])
        rows = rows[np.argsort(rows[:, 0])]
        out.append((step * dt, rows[:, 1:4]))
        k += 9 + n
    return out


def angle_com(x: np.ndarray) -> float:
    """The free surface's angle to the horizontal (degrees) from the bed's centroid in x-z; positive
    when the bed is lifted on the -x side (the drum turns about +y: its bottom moves towards -x)."""
    cx, cz = x[:, 0].mean(), x[:, 2].mean()
    return math.degrees(math.atan2(-cx, -cz))


def angle_surface(x: np.ndarray, radius: float = 0.0016) -> float:
    """The free surface's angle (degrees, the same sign) from a line fitted to the highest sphere
    top in each of 14 bins of x across the middle 70 % of the drum."""
    edges = np.linspace(-0.7 * R, 0.7 * R, 15)
    xs, zs = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        sel = (x[:, 0] >= a) & (x[:, 0] < b)
        if sel.any():
            xs.append(0.5 * (a + b))
            zs.append(x[sel, 2].max() + radius)
    slope = np.polyfit(xs, zs, 1)[0]
    return math.degrees(math.atan(-slope))


def summary(frames, since):
    late = [x for t, x in frames if t >= since - 1e-9]
    com = np.array([angle_com(x) for x in late])
    surf = np.array([angle_surface(x) for x in late])
    return com.mean(), com.std(), surf.mean(), surf.std(), len(late)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--duration", type=float, default=8.0)
    ap.add_argument("--since", type=float, default=4.0)
    ap.add_argument("--frames", type=int, default=40)
    ap.add_argument("--work", default="drum-compare")
    ap.add_argument("--dashpot", default=str(ROOT / "target" / "release" / "dashpot"))
    ap.add_argument("--plugin-dir", default=None)
    venv = os.environ.get("DASHPOT_LAMMPS_VENV", str(Path.home() / ".cache/dashpot/lammps-venv-2025.7.22.4.0"))
    ap.add_argument("--lmp", default=str(Path(venv) / "bin" / "lmp"))
    ap.add_argument("--skip-lammps", action="store_true")
    args = ap.parse_args()
    work = Path(args.work).resolve()
    work.mkdir(parents=True, exist_ok=True)

    # the start state, to the bit, and the run
    (work / "start.toml").write_text(scene_text(1e-12, 1))
    start = json.loads(dashpot(args, "--scene", str(work / "start.toml"), "--json").stdout)
    (work / "drum.toml").write_text(scene_text(args.duration, args.frames))
    t0 = time.time()
    run = json.loads(dashpot(args, "--scene", str(work / "drum.toml"), "--out", str(work / "dashpot"),
                             "--json").stdout)
    wall_dashpot = time.time() - t0
    dt = run["dt"]
    skin = 0.3 * min(p["diameter"] for p in start["particles"])
    books = (run["energy_initial"] + run["wall_work"] - run["energy"] - run["elastic"]
             - run["dissipated"]["total"]) / run["dissipated"]["total"]
    dash = summary(frames_xyz(work / "dashpot" / "trajectory.xyz"), args.since)
    print(f"dashpot: {len(start['particles'])} spheres, dt = {dt:.4e} s, {run['steps']} steps, "
          f"{wall_dashpot:.0f} s wall")
    print(f"dashpot books: initial {run['energy_initial']:.6e} J + wall work {run['wall_work']:.6e} J "
          f"= energy {run['energy']:.6e} + elastic {run['elastic']:.6e} + dissipated "
          f"{run['dissipated']['total']:.6e} J; residual / dissipated = {books:.2e}")
    print(f"dashpot angle (t >= {args.since} s, {dash[4]} frames): centroid {dash[0]:.2f} ± {dash[1]:.2f}°, "
          f"surface fit {dash[2]:.2f} ± {dash[3]:.2f}°")
    if args.skip_lammps:
        return

    # the same spheres for LAMMPS
    parts = start["particles"]
    lines = ["dashpot drum start", "", f"{len(parts)} atoms", "1 atom types", "",
             f"{-0.045} {0.045} xlo xhi", f"0.0 {0.02688} ylo yhi", f"{-0.045} {0.045} zlo zhi", "", "Atoms # sphere", ""]
    for k, p in enumerate(parts):
        x = p["position"]
        lines.append(f"{k + 1} 1 {p['diameter']!r} 2500.0 {x[0]!r} {x[1]!r} {x[2]!r}")
    (work / "start.data").write_text("\n".join(lines) + "\n")
    every = max(1, round(args.duration / args.frames / dt))
    nsteps = run["steps"]
    t0 = time.time()
    subprocess.run([args.lmp, "-in", str(HERE / "lammps" / "in.drum"), "-var", "data", str(work / "start.data"),
                    "-var", "dt", repr(dt), "-var", "skin", repr(skin), "-var", "nsteps", str(nsteps),
                    "-var", "every", str(every), "-log", str(work / "log.lammps")],
                   check=True, cwd=work, stdout=subprocess.DEVNULL)
    wall_lammps = time.time() - t0
    lmp = summary(frames_dump(work / "drum.dump", dt), args.since)
    print(f"LAMMPS: {nsteps} steps, {wall_lammps:.0f} s wall")
    print(f"LAMMPS angle (t >= {args.since} s, {lmp[4]} frames): centroid {lmp[0]:.2f} ± {lmp[1]:.2f}°, "
          f"surface fit {lmp[2]:.2f} ± {lmp[3]:.2f}°")
    print(f"difference dashpot - LAMMPS: centroid {dash[0] - lmp[0]:+.2f}°, surface fit {dash[2] - lmp[2]:+.2f}°")


if __name__ == "__main__":
    sys.exit(main())
