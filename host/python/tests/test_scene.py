"""DEM scenes from Python: the document `dashpot dem --scene FILE --json` prints, to the bit, for
a scene read from the file or built from keywords; runs split by callbacks give the same bits;
the views follow the engine without copies; the energy balances; refusals name the value."""

import numpy as np
import pytest

import dashpot
from conftest import ROOT, cli

# 300 spheres poured between four walls with friction, rolling and twisting resistance
PILE = ROOT / "examples" / "dem" / "rolling-pile.toml"

# eight spheres in two layers just above the floor, falling and spinning
X = np.array([[0.002 * (i % 2), 0.002 * ((i // 2) % 2), 0.00101 + 0.00201 * (i // 4)] for i in range(8)])
V = np.array([[0.01 * i, -0.02, -0.3] for i in range(8)])
W = np.array([[0.0, 5.0 * i, 1.0] for i in range(8)])
D = np.full(8, 0.002)


def scene_file(tmp_path):
    """The example pile, cut to 2 ms."""
    p = tmp_path / "pile.toml"
    p.write_text(dashpot.Scene.from_toml(PILE).to_toml(duration=0.002))
    return p


def keyword_scene(**over):
    kw = dict(dimension=3, positions=X, velocities=V, angular_velocities=W, diameters=D,
              law=dashpot.ContactLaw("hsd", eps=0.6), tangential=dashpot.TangentialLaw("mindlin", mu=0.3),
              rolling=dashpot.RollingLaw("rolling-sds", k=100.0, mu=0.05),
              twisting={"name": "twisting-sds", "params": {"k": 1e-4, "mu": 1e-5}},
              young=1e7, poisson=0.3, density=2500.0, gravity=[0.0, 0.0, -9.81], duration=0.004,
              walls=[{"point": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0]}])
    kw.update(over)
    return dashpot.Scene(**kw)


WALL = {"wall_seconds", "particle_steps_per_second"}


def same(ref, got):
    assert set(ref) == set(got)
    for k in ref:
        if k not in WALL:
            assert ref[k] == got[k], (k, ref[k], got[k])


def test_a_scene_file_run_from_python_is_dem_json_to_the_bit(tmp_path):
    p = scene_file(tmp_path)
    ref = cli("dem", "--scene", p, "--json")
    sim = dashpot.Scene.from_toml(p)
    assert sim.duration == 0.002 and sim.dimension == 3 and len(sim) == 300
    got = sim.run().result()
    same(ref, got)
    assert got["steps"] > 100 and got["time"] >= 0.002 - got["dt"]
    assert got["rolling"] == "rolling-sds" and len(got["provenance"]) == 4


def test_a_keyword_scene_is_its_scene_file_and_callbacks_do_not_change_the_bits(tmp_path):
    sim = keyword_scene()
    p = tmp_path / "kw.toml"
    p.write_text(sim.to_toml())
    ref = cli("dem", "--scene", p, "--json")
    frames = []
    sim.run(every=2e-4, callback=lambda s: frames.append((s.time, s.positions.copy())))
    same(ref, sim.result())
    # a frame every 2e-4 s (whole steps), and one at the end
    k = round(2e-4 / sim.dt)
    assert len(frames) == -(-sim.steps // k)
    assert frames[-1][0] == sim.time and np.array_equal(frames[-1][1], sim.positions)
    # the same scene from the file, in two runs of half the duration each
    twice = dashpot.Scene.from_toml(p)
    twice.run(0.002)
    twice.run(0.002)
    assert twice.steps == sim.steps and np.array_equal(twice.positions, sim.positions)


def test_the_views_follow_the_engine_without_copies_and_are_read_only():
    sim = keyword_scene()
    x, v, f = sim.positions, sim.velocities, sim.forces
    assert x.shape == (8, 3) and sim.angular_velocities.shape == (8, 3) and sim.radii.shape == (8,)
    assert np.array_equal(x, X) and np.array_equal(v, V) and np.all(sim.radii == 0.001)
    assert not x.flags.writeable and x.base is not None
    with pytest.raises(ValueError):
        x[0, 0] = 1.0
    sim.run(0.001)
    # the same arrays, now showing the state after the run
    assert sim.positions is x and not np.array_equal(x, X)
    assert np.any(f != 0.0)
    m = sim.masses
    assert m[0] == pytest.approx(2500.0 * np.pi / 6 * 0.002**3, rel=1e-12)


def test_energy_balances_on_a_frictional_run():
    sim = keyword_scene()
    e0 = sim.energy()
    sim.run()
    e = sim.energy()
    assert e["initial"] == e0["total"] + e0["elastic"]
    lost = e["dissipated"]["total"]
    assert lost > 0.0 and all(e["dissipated"][k] is not None for k in ["normal", "tangential", "rolling", "twisting"])
    # kinetic + gravity + stored + dissipated is what there was, to the integrator's accuracy
    assert e["total"] + e["elastic"] + lost == pytest.approx(e["initial"], rel=2e-3)


def test_energy_false_skips_the_accounting_and_gives_none_not_zeros():
    sim = keyword_scene(energy=False)
    sim.run()
    e = sim.energy()
    assert e["elastic"] is None and e["dissipated"] is None and e["initial"] is None
    assert e["total"] > 0.0
    # the trajectory is the accounted run's, bit for bit: the accounting only reads the contacts
    ref = keyword_scene()
    ref.run()
    assert np.array_equal(sim.positions, ref.positions)


def test_a_2d_scene_with_a_periodic_box_and_a_generated_packing():
    sim = dashpot.Scene(dimension=2, law="hsd", young=1e7, poisson=0.3, density=2500.0,
                        gravity=[0.0, -9.81], box={"lo": [0.0, 0.0], "hi": [0.02, 0.02], "periodic": [True, False]},
                        walls=[{"point": [0.0, 0.0], "normal": [0.0, 1.0]}],
                        generate={"count": 20, "diameter": [0.0015, 0.002], "lo": [0.0, 0.001],
                                  "hi": [0.02, 0.015], "seed": 4})
    assert len(sim) == 20 and sim.positions.shape == (20, 2) and sim.angular_velocities.shape == (20,)
    assert sim.duration is None
    with pytest.raises(ValueError, match="duration"):
        sim.run()
    sim.run(0.002)
    assert np.all((sim.positions[:, 0] >= 0.0) & (sim.positions[:, 0] <= 0.02))


def test_scene_refusals_name_the_key_and_the_value(tmp_path):
    with pytest.raises(ValueError, match="dimension = 4"):
        keyword_scene(dimension=4, positions=np.zeros((1, 4)), velocities=None, angular_velocities=None,
                      diameters=[0.002])
    with pytest.raises(ValueError, match="velocities has shape"):
        keyword_scene(velocities=np.zeros((8, 2)))
    with pytest.raises(ValueError, match="particle\\[2\\].diameter = -0.002"):
        keyword_scene(diameters=[0.002, 0.002, -0.002, 0.002, 0.002, 0.002, 0.002, 0.002])
    with pytest.raises(ValueError, match="overlap"):
        keyword_scene(positions=np.zeros((8, 3)) + [0.0, 0.0, 0.005])
    with pytest.raises(ValueError, match="did you mean `hsd`"):
        keyword_scene(law="hdd")
    with pytest.raises(ValueError, match="youngg|did you mean"):
        dashpot.Scene.from_toml(_bad_file(tmp_path))
    with pytest.raises(ValueError, match="every = 0"):
        keyword_scene().run(0.001, every=0.0)


def _bad_file(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text(PILE.read_text().replace("young = 1.0e7", "youngg = 1.0e7"))
    return p


def species_scene(**over):
    """Eight spheres of two species (glass and rubber) with their own laws per pair: HSD between
    glass beads, Kuwabara–Kono between rubber ones and for the mixed pairs the top-level law;
    rubber on the floor with friction."""
    kw = dict(dimension=3, positions=X, velocities=V, angular_velocities=W, diameters=D,
              species=[{"name": "glass", "young": 6e7, "poisson": 0.25, "density": 2500.0},
                       {"name": "rubber", "young": 1e7, "poisson": 0.45, "density": 1100.0}],
              particle_species=["glass", "rubber"] * 4,
              law=dashpot.ContactLaw("hsd", eps=0.8),
              pairs=[{"species": ["glass", "glass"], "law": dashpot.ContactLaw("hsd", eps=0.5)},
                     {"species": "rubber", "law": {"name": "kuwabara-kono", "params": {"A": 2e-6}}},
                     {"species": "rubber", "wall": "floor", "law": "hsd",
                      "tangential": dashpot.TangentialLaw("mindlin", mu=0.6)}],
              gravity=[0.0, 0.0, -9.81], duration=0.004,
              walls=[{"name": "floor", "point": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0]}])
    kw.update(over)
    return dashpot.Scene(**kw)


def test_species_and_pair_laws_from_keywords_are_the_scene_file_to_the_bit(tmp_path):
    sim = species_scene()
    assert sim.species == ["glass", "rubber"] * 4
    p = tmp_path / "species.toml"
    p.write_text(sim.to_toml())
    assert "[[species]]" in p.read_text() and "[[pair]]" in p.read_text()
    ref = cli("dem", "--scene", p, "--json")
    got = sim.run().result()
    same(ref, got)
    assert [q["species"] for q in got["particles"]] == ["glass", "rubber"] * 4
    names = {c["pairs"]: c["law"] for c in got["pairs"]["particle_pairs"]}
    assert names == {"glass–glass": "hsd", "rubber–rubber": "kuwabara-kono", "glass–rubber": "hsd"}
    walls = {c["pairs"]: (c["law"], c["tangential"]) for c in got["pairs"]["wall_pairs"]}
    assert walls["rubber–wall 0 ('floor')"] == ("hsd", "mindlin") and walls["glass–wall 0 ('floor')"] == ("hsd", None)
    # the masses follow each particle's species
    m = sim.masses
    assert m[0] == pytest.approx(2500.0 * np.pi / 6 * 0.002**3, rel=1e-12)
    assert m[1] == pytest.approx(1100.0 * np.pi / 6 * 0.002**3, rel=1e-12)


def test_species_refusals_name_the_pair_and_the_key():
    with pytest.raises(ValueError, match="no law for the pair \\(glass, rubber\\)"):
        species_scene(law=None)
    with pytest.raises(ValueError, match="particle_species has 3 names"):
        species_scene(particle_species=["glass"] * 3)
    with pytest.raises(ValueError, match="rubbr.*did you mean `rubber`"):
        species_scene(particle_species=["glass", "rubbr"] * 4)
    with pytest.raises(ValueError, match="young.*and species both given"):
        species_scene(young=1e7)
