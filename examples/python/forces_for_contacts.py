"""Normal forces for a numpy array of contacts from another code (a DEM step, a post-processor):
one call, no copies of contiguous float64 arrays, the GIL released while the law runs.

    python examples/python/forces_for_contacts.py
"""

import time

import numpy as np

import dashpot

n = 1_000_000
rng = np.random.default_rng(0)
delta = rng.uniform(0.0, 1e-5, n)  # overlaps (m)
rate = rng.uniform(-1.0, 1.0, n)  # overlap rates (m/s, > 0 approaching)
mass = np.full(n, 3.9e-4)  # effective masses (kg)
radius = np.full(n, 2.5e-3)  # effective radii (m)

hsd = dashpot.ContactLaw("hsd", eps=0.54).bind(young=6e9, poisson=0.3)
t = time.perf_counter()
f = hsd.force(delta, rate, mass, radius)
dt = time.perf_counter() - t
print(f"{n} HSD forces in {dt * 1e3:.1f} ms ({dt / n * 1e9:.2f} ns per contact); max {f.max():.4e} N")

# a law with memory: the caller keeps its history, zeros at first touch
thornton = dashpot.ContactLaw("thornton", py=1e8).bind(young=6e9, poisson=0.3)
history = np.zeros((n, thornton.history_slots))
f = thornton.force(delta, np.abs(rate), mass, radius, history=history)
print(f"thornton: largest overlap remembered {history[:, 0].max():.4e} m")
