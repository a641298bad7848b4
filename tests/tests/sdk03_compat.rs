//! Backward compatibility with sdk 0.3: HSD, Thornton, JKR, Mindlin, rolling-sds and
//! twisting-sds built against dashpot-sdk 0.3.0, from this repository's own sources at the last
//! 0.3 commit (not a copy in the tree), load in the 0.4 host as laws of series 0.3 and compute
//! as before: the normal laws give the same bits as their 0.4 builds (forces, history, reach,
//! energy), the rolling and twisting springs their closed-form step, and a 0.3 normal law
//! reports the default normal context. A plugin of the next series is refused before any of its
//! code runs.

use dashpot::laws::{EnergyOut, RollingResistance, SdkSeries, TwistingResistance};
use dashpot_sdk::{
    Contact, LawKind, MaterialPair, NormalBatch, NormalContext, ParamValue, RollingBatch, TangentialBatch,
    TwistingBatch,
};
use dashpot_tests::{assert_same_bits, next_series_plugin, registry_03, sdk03_registry};

fn materials() -> MaterialPair {
    MaterialPair::new(7.0e10, 2.7e10).unwrap()
}

fn cycle(n: usize, steps: usize) -> dashpot_tests::Cycle {
    dashpot_tests::load_cycle(n, steps, |_| -1.2e-7)
}

#[test]
fn sdk03_normal_laws_load_as_03_and_give_the_same_bits_with_their_default_context() {
    let Some(old) = sdk03_registry("debug") else {
        return;
    };
    let new = registry_03();
    let kinds: Vec<(String, LawKind)> = old
        .laws
        .iter()
        .map(|l| (l.info.name.to_string(), l.info.kind))
        .collect();
    for (name, kind) in [
        ("hsd", LawKind::Contact),
        ("thornton", LawKind::Contact),
        ("jkr", LawKind::Contact),
        ("mindlin", LawKind::Tangential),
        ("rolling-sds", LawKind::Rolling),
        ("twisting-sds", LawKind::Twisting),
    ] {
        assert!(kinds.contains(&(name.to_string(), kind)), "{name}: {kinds:?}");
    }
    assert!(old.plugins.iter().all(|p| p.series == SdkSeries::V0_3));
    assert!(old.laws.iter().all(|l| !l.info.reads_context));
    let (n, steps) = (13, 90);
    let (mass, radius, delta, rate) = cycle(n, steps);
    let mut tension = false;
    for (name, params) in [
        ("hsd", vec![ParamValue::new("eps", 0.6)]),
        ("thornton", vec![ParamValue::new("py", 3e8)]),
        (
            "jkr",
            vec![ParamValue::new("w", 0.2), ParamValue::new("eps", 0.8)],
        ),
    ] {
        // JKR on a soft pair: its reach |δ_c| ≈ 2.5e-7 m, wide enough for the cycle to sample
        let m = if name == "jkr" {
            MaterialPair::new(1e8, 4e7).unwrap()
        } else {
            materials()
        };
        let mo = old.contact(name, &params).unwrap().bind(&m).unwrap();
        let mn = new.contact(name, &params).unwrap().bind(&m).unwrap();
        let slots = mo.history_slots();
        assert_eq!(slots, mn.history_slots());
        let (mut ho, mut hn) = (vec![0.0; n * slots], vec![0.0; n * slots]);
        let mut jkr_shift: Vec<Option<f64>> = vec![None; n];
        for s in 0..steps {
            let mut outs = Vec::new();
            for (m, h) in [(&mo, &mut ho), (&mn, &mut hn)] {
                let (mut f, mut reach, mut p, mut e) =
                    (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
                let mut x = vec![NormalContext::default(); n];
                let b = NormalBatch {
                    delta: &delta[s],
                    rate: &rate[s],
                    mass: &mass,
                    radius: &radius,
                    slots,
                    history: h,
                    force: &mut f,
                };
                let energy = EnergyOut {
                    power: Some(&mut p),
                    elastic: Some(&mut e),
                };
                let written = m
                    .force_batch_context(b, Some(&mut reach), &mut x, energy)
                    .unwrap();
                assert!(written, "{name}: both builds report their energy");
                outs.push((f, reach, p, e, x));
            }
            let what = |k: &'static str| move |i: usize| format!("{name} {k}, step {s}, contact {i}");
            let ((fo, ro, po, eo, xo), (fnew, rn, pn, en, _)) = (&outs[0], &outs[1]);
            assert_same_bits(fo, fnew, what("force"));
            assert_same_bits(ro, rn, what("reach"));
            assert_same_bits(po, pn, what("power"));
            if name == "jkr" {
                // JKR's elastic energy is measured from touch today, from rupture in 0.3 (a
                // change of reference on purpose): the same energy to a constant per contact
                for i in 0..n {
                    if eo[i] == 0.0 && en[i] == 0.0 {
                        continue;
                    }
                    let shift = en[i] - eo[i];
                    let first = *jkr_shift[i].get_or_insert(shift);
                    assert!(
                        (shift - first).abs() <= 1e-9 * first.abs().max(eo[i].abs()),
                        "{}: {} vs {} (shift {shift:e}, first {first:e})",
                        what("elastic")(i),
                        eo[i],
                        en[i]
                    );
                }
            } else {
                assert_same_bits(eo, en, what("elastic"));
            }
            assert_same_bits(&ho, &hn, what("history"));
            // a 0.3 law reports no context of its own: the default, from its force
            for i in 0..n {
                let c = Contact {
                    delta: delta[s][i],
                    rate: rate[s][i],
                    mass: mass[i],
                    radius: radius[i],
                };
                assert_eq!(
                    xo[i],
                    NormalContext::default_for(&c, fo[i]),
                    "{name} step {s} contact {i}"
                );
            }
            tension |= name == "jkr" && fo.iter().zip(&delta[s]).any(|(f, d)| *d < 0.0 && *f < 0.0);
        }
    }
    assert!(tension, "the cycle takes JKR into tension past touching");
}

/// The 0.3 rolling and twisting springs through the 0.4 host: one step from zero history is
/// ξ = v dt, F = −k ξ − γ v (rolling) and θ = ω dt, M = −k θ − γ ω (twisting), below the cap;
/// the history comes back; a context passed to a 0.3 law (which cannot read it) changes nothing.
#[test]
fn sdk03_rotational_laws_step_as_their_closed_forms() {
    let Some(old) = sdk03_registry("debug") else {
        return;
    };
    let (k, gamma, mu) = (1.0e3, 0.5, 10.0);
    let params = [
        ParamValue::new("k", k),
        ParamValue::new("gamma", gamma),
        ParamValue::new("mu", mu),
    ];
    let rolling = old
        .rolling("rolling-sds", &params)
        .unwrap()
        .bind(&materials())
        .unwrap();
    let twisting = old
        .twisting("twisting-sds", &params)
        .unwrap()
        .bind(&materials())
        .unwrap();
    assert!(!rolling.reads_context() && !twisting.reads_context());
    let dt = 1e-4;
    let (v, w) = ([0.2, -0.1, 0.0], 3.0);
    let context = [NormalContext {
        contact_radius: 1.0,
        cap_force: 2.0,
        damping: 3.0,
    }];
    for x in [&[][..], &context[..]] {
        let (mut hr, mut f) = ([0.0; 3], [[0.0; 3]]);
        let written = rolling
            .force_batch(
                RollingBatch {
                    dt,
                    normal: &[[0.0, 0.0, 1.0]],
                    velocity: &[v],
                    normal_force: &[1.0],
                    delta: &[1e-6],
                    mass: &[1e-3],
                    radius: &[1e-3],
                    context: x,
                    slots: 3,
                    history: &mut hr,
                    force: &mut f,
                },
                EnergyOut::none(),
            )
            .unwrap();
        assert!(!written);
        for a in 0..3 {
            assert_eq!(hr[a], v[a] * dt);
            assert!(
                (f[0][a] - (-k * v[a] * dt - gamma * v[a])).abs() <= 1e-15 * k * dt,
                "{f:?}"
            );
        }
        let (mut hw, mut m) = ([0.0], [0.0]);
        twisting
            .torque_batch(
                TwistingBatch {
                    dt,
                    normal: &[[0.0, 0.0, 1.0]],
                    rate: &[w],
                    normal_force: &[1.0],
                    delta: &[1e-6],
                    mass: &[1e-3],
                    radius: &[1e-3],
                    context: x,
                    slots: 1,
                    history: &mut hw,
                    torque: &mut m,
                },
                EnergyOut::none(),
            )
            .unwrap();
        assert_eq!(hw[0], w * dt);
        assert!(
            (m[0] - (-k * w * dt - gamma * w)).abs() <= 1e-15 * gamma * w,
            "{m:?}"
        );
    }
}

/// The 0.3 Mindlin spring through the 0.4 host, one stick step from zero history: the force
/// opposes the slip, stays under the Coulomb cap, and its elastic energy is that of a linear
/// spring, |F| |v| dt / 2, with nothing dissipated.
#[test]
fn sdk03_mindlin_sticks_as_a_linear_spring() {
    let Some(old) = sdk03_registry("debug") else {
        return;
    };
    let m = old
        .tangential("mindlin", &[ParamValue::new("mu", 0.5)])
        .unwrap()
        .bind(&materials())
        .unwrap();
    let (dt, v) = (1e-6, 1e-3);
    let slots = m.history_slots();
    let (mut h, mut f, mut p, mut e) = (vec![0.0; slots], [[0.0; 3]], [f64::NAN], [f64::NAN]);
    let written = m
        .force_batch_with(
            TangentialBatch {
                dt,
                normal: &[[0.0, 0.0, 1.0]],
                velocity: &[[v, 0.0, 0.0]],
                normal_force: &[10.0],
                delta: &[1e-6],
                mass: &[1e-3],
                radius: &[2.5e-3],
                context: &[],
                slots,
                history: &mut h,
                force: &mut f,
            },
            EnergyOut {
                power: Some(&mut p),
                elastic: Some(&mut e),
            },
        )
        .unwrap();
    assert!(written);
    assert!(f[0][0] < 0.0 && f[0][1] == 0.0 && f[0][2] == 0.0 && -f[0][0] < 0.5 * 10.0);
    assert!(
        (e[0] / (0.5 * -f[0][0] * v * dt) - 1.0).abs() < 1e-12,
        "{e:?} {f:?}"
    );
    assert_eq!(p[0], 0.0);
}

/// A plugin of a series this host does not speak (0.5) is refused, both versions named.
#[test]
fn the_next_series_is_refused_naming_both_versions() {
    let e = dashpot_sdk::abi::LoadedPlugin::load(&next_series_plugin()).unwrap_err();
    assert_eq!(e.kind, dashpot_sdk::ErrorKind::Load);
    assert!(
        e.message.contains("built against dashpot-sdk 0.5.0")
            && e.message.contains(&format!(
                "this host uses dashpot-sdk {}",
                dashpot_sdk::abi::ABI_VERSION
            ))
            && e.message
                .contains("loads plugins of sdk 0.1, 0.2, 0.3 and 0.4 only"),
        "{}",
        e.message
    );
}
