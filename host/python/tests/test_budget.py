"""Know before a run, from Python: a scene or a bed past the machine's memory, or one whose steps
would never end, is refused with the words the CLI uses (ValueError), before it allocates or
steps; ``Scene.check()`` estimates steps, peak memory and wall time without touching the scene;
absurd inputs near the limits of f64 and of memory are each refused or run, none aborts or
hangs."""

import math

import pytest

import dashpot

SOFT = dict(young=1e7, poisson=0.3, density=2500.0)


def generated(count, diameter=(0.002, 0.003), hi=0.05, **over):
    kw = dict(dimension=3, law="hsd", gravity=[0.0, 0.0, -9.81], duration=0.002,
              generate={"count": count, "diameter": list(diameter), "lo": [0.0, 0.0, 0.0],
                        "hi": [hi, hi, hi], "seed": 5},
              walls=[{"point": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0]}])
    kw.update(SOFT)
    kw.update(over)
    return dashpot.Scene(**kw)


def test_a_scene_past_the_memory_is_refused_naming_the_count_and_the_memory():
    with pytest.raises(ValueError, match=r"generate\.count = 1000000000000 particles would need about "
                                         r"[0-9.]+ TiB of memory .* is available"):
        generated(10**12, hi=100.0)


def test_check_estimates_steps_memory_and_time_without_touching_the_scene():
    sim = generated(60)
    est = sim.check(sample=0.2)
    assert est["steps"] == math.ceil(sim.duration / sim.dt)
    assert est["dt"] == sim.dt
    # the peak counts what the process holds and the run's parts, each positive
    assert est["memory_bytes"] > 0 and all(b > 0 for b in est["memory_parts"].values())
    assert "contacts" in est["memory_parts"] and "particles" in est["memory_parts"]
    assert 0 < est["memory_bytes"] - sum(est["memory_parts"].values()) <= est["memory_bytes"]
    assert est["wall_seconds"] > 0 and est["seconds_per_step"] > 0 and est["sample_steps"] >= 1
    # the scene itself did not move
    assert sim.steps == 0 and sim.time == 0.0
    with pytest.raises(ValueError, match="sample = 0"):
        sim.check(sample=0.0)


def test_steps_past_any_machine_are_refused_by_run_and_by_check():
    for over in [dict(young=1e308), dict(dt=1e-300), dict(steps_per_collision=1e12),
                 dict(law=dashpot.ContactLaw("lsd", k=1e300, eps=0.5))]:
        sim = generated(10, **over)
        with pytest.raises(ValueError, match=r"steps, beyond the 1e\+?12"):
            sim.run()
        with pytest.raises(ValueError, match="steps, beyond"):
            sim.check(sample=0.1)
        assert sim.steps == 0
    # a long duration from a sane step: refused as well, and a short run still goes
    sim = generated(10)
    with pytest.raises(ValueError, match="steps, beyond"):
        sim.run(1e300)
    sim.run(2 * sim.dt)
    assert sim.steps == 2


def test_particles_without_a_size_or_a_finite_mass_are_refused():
    for d, text in [(5e-324, "5e-324"), (1e-320, "1e-320"), (1e300, "1e300")]:
        with pytest.raises(ValueError, match=f"diameter = {text} m"):
            generated(10, diameter=(d, d), hi=max(0.05, 10 * d))


def test_grids_and_beds_past_the_machine_are_refused():
    with pytest.raises(ValueError, match="1000000000000 collisions .* of memory"):
        dashpot.sweep("hsd", v0="1:2:1000000", vary={"eps": "0.1:0.9:1000000"})
    with pytest.raises(ValueError, match="COUNT"):
        dashpot.sweep("hsd", v0="1e-3:10:1000000000000")
    with pytest.raises(ValueError, match="layers"):
        dashpot.bed(1e12, 20, restitution="mcnamara-falcon")
    with pytest.raises(ValueError, match="of memory"):
        dashpot.bed(1e12, 20, law="hsd")
    with pytest.raises(ValueError, match="steps, beyond"):
        dashpot.bed(0.1, 20, law="hsd", young=1e308)
    with pytest.raises(ValueError, match="seeds"):
        dashpot.bed(0.1, 20, restitution="constant", seeds=10**9)
