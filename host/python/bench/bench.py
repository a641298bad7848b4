"""Benchmarks of the Python package, each a ratio against a baseline measured in the same run
(the contenders alternate; the median of the pairs is reported):

1. HSD forces on 10⁶ contacts through Python (`BoundContactLaw.force` into a reused `out`)
   against the Rust batch call on the same arrays and law handle (target ≥ 0.9);
2. the same against the HSD formula written in numpy (target ≥ 10);
3. a calibration loop (HSD collisions of MCC spheres, random ε and v0) through
   `dashpot.collide` against scipy's solve_ivp (DOP853, event at δ = 0, rtol 1e-10) (target ≥ 500).

    DASHPOT_PLUGIN_PATH=target/release python host/python/bench/bench.py
"""

import math
import statistics
import time

import numpy as np

import dashpot

E_EFF = 6e9 / (2 * (1 - 0.3**2))


def hsd_numpy(delta, rate, mass, radius, eps):
    l = math.log(eps)
    alpha = -math.sqrt(5.0) * l / math.sqrt(l * l + math.pi**2)
    k = 4.0 / 3.0 * E_EFF * np.sqrt(radius)
    d = np.maximum(delta, 0.0)
    return k * d**1.5 + alpha * np.sqrt(mass * k) * d**0.25 * rate


def median_ratio(baseline, contender, pairs):
    """Median over `pairs` alternating runs of baseline time / contender time (the speed ratio)."""
    ratios = []
    for _ in range(pairs):
        tb = baseline()
        tc = contender()
        ratios.append(tb / tc)
    return statistics.median(ratios), ratios


def forces():
    n = 1_000_000
    rng = np.random.default_rng(3)
    delta = rng.uniform(0.0, 1e-5, n)
    rate = rng.uniform(-1.0, 1.0, n)
    mass = rng.uniform(1e-4, 1e-3, n)
    radius = rng.uniform(1e-3, 5e-3, n)
    b = dashpot.ContactLaw("hsd", eps=0.3).bind(young=6e9, poisson=0.3)
    assert np.allclose(b.force(delta, rate, mass, radius), hsd_numpy(delta, rate, mass, radius, 0.3), rtol=1e-12)

    def rust():
        return min(b._inner._time_batch(delta, rate, mass, radius, 3))

    out = np.empty(n)

    def python():
        best = math.inf
        for _ in range(3):
            t = time.perf_counter()
            b.force(delta, rate, mass, radius, out=out)
            best = min(best, time.perf_counter() - t)
        return best

    def numpy_hsd():
        best = math.inf
        for _ in range(3):
            t = time.perf_counter()
            hsd_numpy(delta, rate, mass, radius, 0.3)
            best = min(best, time.perf_counter() - t)
        return best

    r1, p1 = median_ratio(rust, python, 7)
    r2, p2 = median_ratio(numpy_hsd, python, 7)
    print(f"1. forces on 10^6 contacts: Python / Rust batch (speed) median {r1:.3f}  pairs {[round(x, 3) for x in p1]}  target >= 0.9")
    print(f"2. forces on 10^6 contacts: Python / numpy HSD (speed) median {r2:.2f}  pairs {[round(x, 2) for x in p2]}  target >= 10")


def calibration():
    try:
        from scipy.integrate import solve_ivp
    except ImportError:
        print("3. (scipy not installed: the calibration benchmark is skipped)")
        return
    d, rho = 0.01, 1500.0
    m = math.pi / 12.0 * rho * d**3
    k = 4.0 / 3.0 * E_EFF * math.sqrt(d / 4.0)
    rng = np.random.default_rng(1)
    cases = [(0.01 + 0.98 * rng.random(), 10 ** rng.uniform(-3, 1)) for _ in range(400)]

    def scipy_e(eps, v0):
        l = math.log(eps)
        c = -math.sqrt(5.0) * l / math.sqrt(l * l + math.pi**2) * math.sqrt(m * k)

        def rhs(_t, y):
            dd = max(y[0], 0.0)
            return [y[1], -(k * dd**1.5 + c * dd**0.25 * y[1]) / m]

        def back(_t, y):
            return y[0]

        back.terminal, back.direction = True, -1
        dmax = (5.0 * m * v0 * v0 / (4.0 * k)) ** 0.4
        s = solve_ivp(rhs, (0.0, 100.0 * dmax / v0), [0.0, v0], method="DOP853", rtol=1e-10,
                      atol=[1e-13 * dmax, 1e-13 * v0], events=back)
        return -s.y_events[0][0][1] / v0

    def run_scipy():
        t = time.process_time()
        for eps, v0 in cases[:20]:
            scipy_e(eps, v0)
        return (time.process_time() - t) / 20

    def run_dashpot():
        t = time.process_time()
        for eps, v0 in cases:
            dashpot.collide("hsd", v0=v0, eps=eps, rtol=1e-9)
        return (time.process_time() - t) / len(cases)

    r, p = median_ratio(run_scipy, run_dashpot, 3)
    print(f"3. calibration loop, one collision: dashpot.collide / scipy solve_ivp (speed) median {r:.0f}  pairs {[round(x) for x in p]}  target >= 500")


if __name__ == "__main__":
    forces()
    calibration()
