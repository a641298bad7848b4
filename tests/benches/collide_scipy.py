#!/usr/bin/env python3
"""SciPy baseline for the collision benchmark: HSD head-on collisions of two 1 cm MCC spheres
(Antypov & Elliott 2011) with solve_ivp(method="DOP853"), event at overlap = 0.

Setup (once):   python3 -m venv /tmp/scipy-venv && /tmp/scipy-venv/bin/pip install scipy numpy
Run it alone:   /tmp/scipy-venv/bin/python tests/benches/collide_scipy.py --rtol 1e-10
Normally it is run by `cargo bench -p dashpot-tests --bench collide` (set DASHPOT_PYTHON to the
venv's python), which prints the ratio against dashpot in the same run.

Prints one JSON line: collisions per second and the largest |realized restitution − eps|.
"""
import argparse
import json
import math
import time

import numpy as np
from scipy.integrate import solve_ivp


def mcc_pair():
    d, rho, young, nu = 0.01, 1500.0, 6.0e9, 0.3
    m_eff = math.pi / 12.0 * rho * d**3
    e_eff = young / (2.0 * (1.0 - nu * nu))
    k_hertz = 4.0 / 3.0 * e_eff * math.sqrt(d / 4.0)
    return m_eff, k_hertz


def hsd_collision(eps, v0, m, k, rtol):
    l = math.log(eps)
    alpha = -math.sqrt(5.0) * l / math.sqrt(l * l + math.pi**2)
    c = alpha * math.sqrt(m * k)

    def rhs(_t, y):
        d = max(y[0], 0.0)
        return [y[1], -(k * d**1.5 + c * d**0.25 * y[1]) / m]

    def back_to_zero(_t, y):
        return y[0]

    back_to_zero.terminal = True
    back_to_zero.direction = -1
    dmax = (5.0 * m * v0 * v0 / (4.0 * k)) ** 0.4
    t_end = 100.0 * dmax / v0
    sol = solve_ivp(rhs, (0.0, t_end), [0.0, v0], method="DOP853", rtol=rtol,
                    atol=[rtol * dmax * 1e-3, rtol * v0 * 1e-3], events=back_to_zero)
    v_end = sol.y_events[0][0][1]
    return -v_end / v0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtol", type=float, default=1e-10)
    ap.add_argument("--seconds", type=float, default=5.0)
    a = ap.parse_args()
    m, k = mcc_pair()
    rng = np.random.default_rng(1)
    n, worst, t0 = 0, 0.0, time.process_time()
    while time.process_time() - t0 < a.seconds:
        eps = 0.01 + 0.98 * rng.random()
        v0 = 10.0 ** (-3.0 + 4.0 * rng.random())
        worst = max(worst, abs(hsd_collision(eps, v0, m, k, a.rtol) - eps))
        n += 1
    dt = time.process_time() - t0
    print(json.dumps({"collisions_per_second": n / dt, "collisions": n, "max_eps_error": worst, "rtol": a.rtol}))


if __name__ == "__main__":
    main()
