"""A DEM scene from Python: spheres poured onto a floor, the trajectory read every millisecond
through numpy views of the engine's arrays, the energy balance at the end, and the scene file
that `dashpot dem --scene` runs to the same bits.

    python examples/python/run_scene.py
"""

import os
import tempfile

import numpy as np

import dashpot

# 27 glass beads of 2 mm in a 3 × 3 × 3 lattice, 1 mm apart, falling on a floor; softened to
# E = 1e7 Pa (a step of ~2 µs instead of ~0.2 µs; see docs/dem.md)
grid = np.arange(3) * 0.003
positions = np.array([[x, y, 0.002 + z] for z in grid for y in grid for x in grid])
rng = np.random.default_rng(1)
velocities = rng.normal(0.0, 0.05, positions.shape)

sim = dashpot.Scene(
    dimension=3,
    positions=positions,
    velocities=velocities,
    diameters=np.full(len(positions), 0.002),
    law=dashpot.ContactLaw("hsd", eps=0.5),
    tangential=dashpot.TangentialLaw("mindlin", mu=0.3),
    rolling=dashpot.RollingLaw("rolling-sds", k=100.0, mu=0.05),
    young=1e7,
    poisson=0.3,
    density=2500.0,
    gravity=[0.0, 0.0, -9.81],
    walls=[{"point": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0]}],
)
print(sim, f"(contact time {sim.step_choice()['collision_time']:.3e} s)")

# the trajectory: a copy of the positions every millisecond (the views themselves follow the run)
times, frames = [], []
sim.run(0.05, every=1e-3, callback=lambda s: (times.append(s.time), frames.append(s.positions.copy())))
trajectory = np.stack(frames)  # (frames, particles, 3)
height = trajectory[:, :, 2].mean(axis=1)
print(f"{len(frames)} frames; mean height {height[0] * 1e3:.3f} mm -> {height[-1] * 1e3:.3f} mm")
print(f"lowest sphere centre now {sim.positions[:, 2].min() * 1e3:.4f} mm (radius 1 mm); "
      f"largest contact force {np.linalg.norm(sim.forces, axis=1).max():.3e} N")

e = sim.energy()
balance = e["total"] + e["elastic"] + e["dissipated"]["total"]
print(f"energy: initial {e['initial']:.6e} J = now {e['total']:.6e} + stored {e['elastic']:.3e} "
      f"+ dissipated {e['dissipated']['total']:.6e} (off by {abs(balance - e['initial']) / abs(e['initial']):.1e})")

# what the CLI would print for the same scene and duration: `dashpot dem --scene pour.toml --json`
path = os.path.join(tempfile.mkdtemp(), "pour.toml")
with open(path, "w") as f:
    f.write(sim.to_toml(duration=0.05))
r = sim.result()
print(f"result: {r['steps']} steps of {r['dt']:.3e} s, {r['contacts']} contacts now; the scene file: {path}")
