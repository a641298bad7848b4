"""Fit a contact law to a measured restitution curve e(v) with scipy.optimize, through
dashpot.collide, and plot it with matplotlib.

The "measurements" are Kuwabara–Kono collisions of 1 cm MCC spheres at A = 2e-6 s with 1 %
noise; the fit finds A back. Each call of `dashpot.collide` with an array of speeds computes the
whole curve (its collisions in lockstep, each the bits of a single collision). With the
package installed (`pip install ./host/python`) and
SciPy and matplotlib:

    python examples/python/fit_restitution.py
"""

import numpy as np
from scipy.optimize import minimize_scalar

import dashpot

rng = np.random.default_rng(1)
speeds = np.logspace(-2, 1, 12)  # m/s
truth = 2e-6  # s
measured = dashpot.collide("kuwabara-kono", v0=speeds, end="force", A=truth)["restitution"]
measured = measured * (1 + 0.01 * rng.standard_normal(speeds.size))


def misfit(log_a: float) -> float:
    e = dashpot.collide("kuwabara-kono", v0=speeds, end="force", A=10**log_a)["restitution"]
    return float(np.sum((e - measured) ** 2))


best = minimize_scalar(misfit, bounds=(-8, -4), method="bounded", options={"xatol": 1e-4})
a_fit = 10**best.x
print(f"fitted A = {a_fit:.4e} s (truth {truth:.1e} s), {best.nfev} evaluations of {speeds.size} collisions")

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fine = np.logspace(-2, 1, 60)
    fit = dashpot.collide("kuwabara-kono", v0=fine, end="force", A=a_fit)["restitution"]
    plt.semilogx(speeds, measured, "o", label="measured")
    plt.semilogx(fine, fit, "-", label=f"Kuwabara–Kono, A = {a_fit:.3e} s")
    plt.xlabel("impact speed v0 (m/s)")
    plt.ylabel("coefficient of restitution")
    plt.legend()
    plt.savefig("fit_restitution.png", dpi=120)
    print("wrote fit_restitution.png")
except ImportError:
    print("(matplotlib not installed: no plot)")
