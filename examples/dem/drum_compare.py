#!/usr/bin/env python3
"""The rotating drum of examples/dem/drum.toml in dashpot and in LAMMPS (examples/dem/lammps/in.drum):
the dynamic angle of repose of each, and dashpot's energy books.

    python3 examples/dem/drum_compare.py [--duration 8] [--since 4] [--frames 80] [--dt DT]
        [--work DIR] [--dashpot PATH] [--plugin-dir DIR] [--lmp PATH] [--skip-lammps]
    python3 examples/dem/drum_compare.py --measure-only --work DIR [--since 4]
    python3 examples/dem/drum_compare.py --measure FILE [--since T] [--dt DT] [--radius R]

dashpot runs the scene with --out (a frame every duration/frames); LAMMPS runs at the same time from
the same spheres (dashpot's state at t = 0, written as a LAMMPS data file), with the same step, skin,
material and laws (read from the scene), and dumps the positions at the same times. --measure-only
measures the outputs of an earlier run in --work again; --measure measures one trajectory (dashpot's
.xyz, or a LAMMPS dump with columns x, z, radius, given --dt) and prints the angles as JSON.
The angle of each frame, two ways:

- from the centre of mass of the spheres (weighted by r^3) in the x-z plane: the bed of a half-full drum is a
  circular segment, whose centroid lies on the perpendicular to its free surface through the
  drum's axis, so the surface's angle to the horizontal is the angle of that centroid from the
  vertical (exact for a flat surface at any fill);
- from a line fitted to the free surface: in bins of x across the middle 70 % of the drum's
  diameter, the top of the highest sphere in each bin, fitted by least squares.

Each is averaged over the frames from --since on (the bed has left its start and flows steadily);
the spread is the frames' standard deviation. Python's standard library only; LAMMPS from $DASHPOT_LAMMPS_VENV/bin/lmp
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

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
R = 0.04  # the drum's radius (m), as in drum.toml


def scene_text(duration: float, frames: int, dt=None) -> str:
    text = (HERE / "drum.toml").read_text()
    text = re.sub(r"^duration = .*$", f"duration = {duration!r}", text, count=1, flags=re.M)
    if dt is not None:
        text = re.sub(r"^duration = .*$", lambda m: f"{m.group(0)}\ndt = {dt!r}", text, count=1, flags=re.M)
    return re.sub(r"^snapshots = .*$", f"snapshots = {frames}", text, count=1, flags=re.M)


def dashpot(args, *extra):
    cmd = [args.dashpot]
    if args.plugin_dir:
        cmd += ["--no-default-plugins", "--plugin-dir", args.plugin_dir]
    return subprocess.run(cmd + ["dem", *extra], check=True, capture_output=True, text=True)


def frames_xyz(path: Path):
    """(time, spheres [(x, z, radius)]) of each frame of dashpot's extended XYZ trajectory."""
    out = []
    lines = path.read_text().splitlines()
    k = 0
    while k < len(lines) and lines[k].strip():
        n = int(lines[k])
        if len(lines) < k + 2 + n:
            raise ValueError(f"{path}: the frame at line {k + 1} is cut short ({len(lines) - k - 2} of {n} spheres)")
        head = lines[k + 1]
        t = float(re.search(r"Time=(\S+)", head).group(1))
        # the columns: Properties=name:type:count:... ; find pos and radius
        props = re.search(r"Properties=(\S+)", head).group(1).split(":")
        col, cols = 0, {}
        for name, count in zip(props[0::3], props[2::3]):
            cols[name] = col
            col += int(count)
        ix, ir = cols["pos"], cols["radius"]
        frame = []
        for line in lines[k + 2:k + 2 + n]:
            v = line.split()
            frame.append((float(v[ix]), float(v[ix + 2]), float(v[ir])))
        out.append((t, frame))
        k += 2 + n
    return out


def frames_dump(path: Path, dt: float):
    """(time, spheres [(x, z, radius)]) of each frame of a LAMMPS custom dump (id x y z radius)."""
    out = []
    lines = path.read_text().splitlines()
    k = 0
    while k < len(lines) and lines[k].strip():
        step = int(lines[k + 1])
        n = int(lines[k + 3])
        if len(lines) < k + 9 + n:
            raise ValueError(f"{path}: the frame at line {k + 1} is cut short ({len(lines) - k - 9} of {n} atoms)")
        names = lines[k + 8].split()[2:]
        ix, iz, ir = names.index("x"), names.index("z"), names.index("radius")
        frame = []
        for line in lines[k + 9:k + 9 + n]:
            v = line.split()
            frame.append((float(v[ix]), float(v[iz]), float(v[ir])))
        out.append((step * dt, frame))
        k += 9 + n
    return out


def angle_centroid(spheres) -> float:
    """The free surface's angle to the horizontal (degrees) from the bed's centre of mass in x-z
    (spheres weighted by r^3), measured from the drum's axis (x = z = 0); positive when the bed is
    lifted on the -x side (the drum turns about +y: its bottom moves towards -x)."""
    m = sum(r**3 for _, _, r in spheres)
    cx = sum(x * r**3 for x, _, r in spheres) / m
    cz = sum(z * r**3 for _, z, r in spheres) / m
    return math.degrees(math.atan2(-cx, -cz))


def angle_surface(spheres, radius: float, bins: int = 14, span: float = 0.7) -> float:
    """The free surface's angle (degrees, the same sign) from a line fitted by least squares to the
    top (centre + radius) of the highest sphere in each of `bins` bins of x across the middle
    `span` of the drum's diameter (`radius`: the drum's, m)."""
    lo, w = -span * radius, 2.0 * span * radius / bins
    top = {}
    for x, z, r in spheres:
        b = math.floor((x - lo) / w)
        if 0 <= b < bins and (b not in top or z + r > top[b][1]):
            top[b] = (x, z + r)
    if len(top) < 3:
        raise ValueError(f"only {len(top)} of {bins} bins across the drum hold a sphere: no surface to fit")
    pts = list(top.values())
    mx = sum(p[0] for p in pts) / len(pts)
    mz = sum(p[1] for p in pts) / len(pts)
    slope = sum((p[0] - mx) * (p[1] - mz) for p in pts) / sum((p[0] - mx) ** 2 for p in pts)
    return math.degrees(math.atan(-slope))


def mean_std(v):
    m = sum(v) / len(v)
    return m, math.sqrt(sum((a - m) ** 2 for a in v) / len(v))


def summary(frames, since, radius=R):
    """The two angles' means and standard deviations (degrees) over the frames at t >= since (s):
    {"frames", "centroid": [mean, std], "surface": [mean, std], "times", "centroid_each",
    "surface_each"}."""
    late = [(t, s) for t, s in frames if t >= since - 1e-9]
    if not late:
        raise ValueError(f"no frame at t >= {since} s (the last is at {frames[-1][0] if frames else '-'} s)")
    com = [angle_centroid(s) for _, s in late]
    surf = [angle_surface(s, radius) for _, s in late]
    return {"frames": len(late), "centroid": mean_std(com), "surface": mean_std(surf),
            "times": [t for t, _ in late], "centroid_each": com, "surface_each": surf}


def measure(path: Path, since: float, dt, radius: float):
    """The angles of a trajectory file: dashpot's XYZ (*.xyz) or a LAMMPS dump (needs dt)."""
    if path.suffix == ".xyz":
        return summary(frames_xyz(path), since, radius)
    if dt is None:
        raise ValueError(f"{path}: a LAMMPS dump's times need --dt (the step, s)")
    return summary(frames_dump(path, dt), since, radius)


def steps_to(duration: float, dt: float) -> int:
    """The number of steps dashpot takes to reach `duration` (s) at step `dt` (s)."""
    k, t = 0, 0.0
    while t + 0.5 * dt < duration:
        t += dt
        k += 1
    return k


def lammps_data(parts, scene) -> str:
    """A LAMMPS data file (atom_style sphere) of dashpot's spheres in the scene's box."""
    lo, hi = scene["box"]["lo"], scene["box"]["hi"]
    rho = scene["material"]["density"]
    lines = ["dashpot drum start", "", f"{len(parts)} atoms", "1 atom types", "",
             f"{lo[0]!r} {hi[0]!r} xlo xhi", f"{lo[1]!r} {hi[1]!r} ylo yhi", f"{lo[2]!r} {hi[2]!r} zlo zhi", "",
             "Atoms # sphere", ""]
    for k, p in enumerate(parts):
        x = p["position"]
        lines.append(f"{k + 1} 1 {p['diameter']!r} {rho!r} {x[0]!r} {x[1]!r} {x[2]!r}")
    return "\n".join(lines) + "\n"


def lammps_vars(scene):
    """The deck's variables (-var NAME VALUE) from the scene: the drum, the material, the laws."""
    (drum,) = [w for w in scene["wall"] if w.get("kind") == "cylinder"]
    m, law, tan, rol = scene["material"], scene["law"], scene["tangential"], scene["rolling"]
    if (law["name"], tan["name"], rol["name"]) != ("hsd", "mindlin", "rolling-sds"):
        raise ValueError("in.drum maps hsd + mindlin + rolling-sds only")
    if tan["params"].get("damping", 0.0) != 0.0:
        raise ValueError("in.drum maps mindlin without tangential damping only")
    v = {"eps": law["params"]["eps"], "mu": tan["params"]["mu"], "kr": rol["params"]["k"],
         "gr": rol["params"]["gamma"], "mur": rol["params"]["mu"], "E": m["young"], "nu": m["poisson"],
         "R": drum["radius"], "rpm": drum["motion"]["rpm"]}
    return [a for k, x in v.items() for a in ("-var", k, repr(float(x)))]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--duration", type=float, default=8.0)
    ap.add_argument("--since", type=float, default=4.0)
    ap.add_argument("--frames", type=int, default=80)
    ap.add_argument("--dt", type=float, default=None, help="the step (s); default: dashpot's choice")
    ap.add_argument("--work", default="drum-compare")
    ap.add_argument("--dashpot", default=str(ROOT / "target" / "release" / "dashpot"))
    ap.add_argument("--plugin-dir", default=None)
    venv = os.environ.get("DASHPOT_LAMMPS_VENV", str(Path.home() / ".cache/dashpot/lammps-venv-2025.7.22.4.0"))
    ap.add_argument("--lmp", default=str(Path(venv) / "bin" / "lmp"))
    ap.add_argument("--skip-lammps", action="store_true")
    ap.add_argument("--measure-only", action="store_true",
                    help="measure the outputs already in --work (dashpot/trajectory.xyz, drum.dump)")
    ap.add_argument("--measure", metavar="FILE", default=None,
                    help="only measure FILE (dashpot's .xyz or a LAMMPS dump, with --dt) from --since on, "
                         "with --radius; print the angles as JSON")
    ap.add_argument("--radius", type=float, default=R, help="the drum's radius (m) for --measure")
    args = ap.parse_args()
    if args.measure is not None:
        try:
            m = measure(Path(args.measure), args.since, args.dt, args.radius)
        except (OSError, ValueError, KeyError, IndexError, AttributeError) as err:
            sys.exit(f"drum_compare: cannot measure {args.measure}: {err!r}")
        print(json.dumps({k: m[k] for k in ("frames", "centroid", "surface")}))
        return
    work = Path(args.work).resolve()
    work.mkdir(parents=True, exist_ok=True)

    if not args.measure_only:
        # the start state, to the bit; then both runs side by side
        (work / "start.toml").write_text(scene_text(1e-12, 1, args.dt))
        start = json.loads(dashpot(args, "--scene", str(work / "start.toml"), "--json").stdout)
        dt = start["dt"]
        import tomllib  # Python >= 3.11; --measure needs only the standard library of 3.8

        scene = tomllib.loads(scene_text(args.duration, args.frames, args.dt))
        (work / "start.data").write_text(lammps_data(start["particles"], scene))
        skin = 0.3 * min(p["diameter"] for p in start["particles"])
        every = max(1, round(args.duration / args.frames / dt))
        nsteps = steps_to(args.duration, dt)
        (work / "meta.json").write_text(json.dumps({"dt": dt, "nsteps": nsteps, "every": every}))
        lmp_run = None
        if not args.skip_lammps:
            lmp_run = subprocess.Popen(
                [args.lmp, "-in", str(HERE / "lammps" / "in.drum"), "-var", "data", str(work / "start.data"),
                 "-var", "dt", repr(dt), "-var", "skin", repr(skin), "-var", "nsteps", str(nsteps),
                 "-var", "every", str(every), *lammps_vars(scene), "-log", str(work / "log.lammps")],
                cwd=work, stdout=subprocess.DEVNULL)
        (work / "drum.toml").write_text(scene_text(args.duration, args.frames, args.dt))
        t0 = time.time()
        out = dashpot(args, "--scene", str(work / "drum.toml"), "--out", str(work / "dashpot"), "--json").stdout
        (work / "dashpot.json").write_text(out)
        print(f"dashpot: {len(start['particles'])} spheres, dt = {dt:.4e} s, {nsteps} steps, "
              f"{time.time() - t0:.0f} s wall")
        if lmp_run is not None and lmp_run.wait() != 0:
            sys.exit(f"LAMMPS failed (exit {lmp_run.returncode}): see {work / 'log.lammps'}")
        print(f"LAMMPS: {nsteps} steps, {time.time() - t0:.0f} s wall")
    dt = json.loads((work / "meta.json").read_text())["dt"]
    run = json.loads((work / "dashpot.json").read_text())
    books = (run["energy_initial"] + run["wall_work"] - run["energy"] - run["elastic"]
             - run["dissipated"]["total"]) / run["dissipated"]["total"]
    print(f"dashpot books: initial {run['energy_initial']:.6e} J + wall work {run['wall_work']:.6e} J "
          f"= energy {run['energy']:.6e} + elastic {run['elastic']:.6e} + dissipated "
          f"{run['dissipated']['total']:.6e} J; residual / dissipated = {books:.2e}")
    dash = summary(frames_xyz(work / "dashpot" / "trajectory.xyz"), args.since)
    report("dashpot", dash, args.since)
    if args.skip_lammps:
        return
    lmp = summary(frames_dump(work / "drum.dump", dt), args.since)
    report("LAMMPS", lmp, args.since)
    with open(work / "angles.csv", "w") as f:
        f.write("time_s,dashpot_centroid_deg,dashpot_surface_deg,lammps_centroid_deg,lammps_surface_deg\n")
        for k, t in enumerate(dash["times"]):
            if k < lmp["frames"]:
                f.write(f"{t:.4f},{dash['centroid_each'][k]:.3f},{dash['surface_each'][k]:.3f},"
                        f"{lmp['centroid_each'][k]:.3f},{lmp['surface_each'][k]:.3f}\n")
    print(f"difference dashpot - LAMMPS: centroid {dash['centroid'][0] - lmp['centroid'][0]:+.2f}°, "
          f"surface fit {dash['surface'][0] - lmp['surface'][0]:+.2f}° (frame by frame: {work / 'angles.csv'})")


def report(who, m, since):
    print(f"{who} angle (t >= {since} s, {m['frames']} frames): centroid {m['centroid'][0]:.2f} ± "
          f"{m['centroid'][1]:.2f}°, surface fit {m['surface'][0]:.2f} ± {m['surface'][1]:.2f}°")


if __name__ == "__main__":
    sys.exit(main())
