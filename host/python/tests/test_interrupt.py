"""Ctrl-C (SIGINT) stops a long run cleanly: a child Python process starts a run that would
last hours (or seconds: a sweep, a restitution curve), the test sends it SIGINT, and the child catches KeyboardInterrupt within a second or
two, reports where the run stood, and exits 0; no panic, no thread left running."""

import os
import signal
import subprocess
import sys
import time

import pytest

CHILD = r"""
import sys, time, dashpot
what = sys.argv[1]
print("running", flush=True)
t0 = time.monotonic()
try:
    if what == "scene":
        sim = dashpot.Scene(dimension=3, positions=[[0.0, 0.0, 0.01]], diameters=[0.002], law="hsd",
                            young=1e7, poisson=0.3, density=2500.0, gravity=[0.0, 0.0, -9.81],
                            walls=[{"point": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0]}])
        sim.run(1e6)
    elif what == "bed":
        dashpot.bed(restitution="mcnamara-falcon", layers=1, freq=20, cycles=1e7, transient=0)
    elif what == "sweep":
        dashpot.sweep("kuwabara-kono", v0="1e-3:10:1000000", end="force")
    elif what == "curve":
        import numpy as np
        dashpot.collide("kuwabara-kono", v0=np.logspace(-3, 1, 1000000), end="force")
    print("finished", flush=True)
except KeyboardInterrupt:
    state = f" at step {sim.steps}, t = {sim.time} s" if what == "scene" else ""
    # the scene stays usable after the interrupt
    if what == "scene":
        sim.run(sim.dt)
    print(f"KeyboardInterrupt{state} after {time.monotonic() - t0:.2f} s", flush=True)
    sys.exit(0)
"""


@pytest.mark.parametrize("what", ["scene", "bed", "sweep", "curve"])
def test_sigint_stops_a_long_run_with_a_keyboard_interrupt(what):
    p = subprocess.Popen([sys.executable, "-c", CHILD, what], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True, env=dict(os.environ))
    assert p.stdout.readline().strip() == "running"
    time.sleep(1.0)
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=30)
    waited = time.monotonic() - sent
    assert p.returncode == 0, (out, err)
    assert "KeyboardInterrupt" in out and "finished" not in out, (out, err)
    assert "panicked" not in err and "Traceback" not in err, err
    assert waited < 5.0, f"the run took {waited:.1f} s to stop"
    if what == "scene":
        assert " at step " in out and " at step 0," not in out
