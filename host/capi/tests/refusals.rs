//! The C ABI refuses what the CLI refuses, with a message readable through
//! `dashpot_last_error`: a closed-form calibration whose stiffness overflows, a law whose
//! coefficients overflow for the pair it is bound to, and a normal that is not a unit vector.

use dashpot_capi::*;
use std::ffi::{CStr, CString};
use std::ptr;

fn last_error() -> String {
    unsafe { CStr::from_ptr(dashpot_last_error()) }
        .to_string_lossy()
        .into_owned()
}

/// The registry of the plugins built beside this test.
fn registry() -> *mut DashpotRegistry {
    let exe = std::env::current_exe().expect("current_exe");
    let dir = CString::new(exe.parent().expect("exe dir").to_str().expect("UTF-8 path")).unwrap();
    let dirs = [dir.as_ptr()];
    let mut reg: *mut DashpotRegistry = ptr::null_mut();
    let st = unsafe { dashpot_registry_open(dirs.as_ptr(), 1, 0, &mut reg) };
    assert_eq!(st, DashpotStatus::DASHPOT_OK, "{}", last_error());
    reg
}

/// Two MCC granules (d = 1 mm, ρ = 1500 kg/m³, E = 6 GPa, ν = 0.3).
fn mcc_pair() -> DashpotPair {
    let p = DashpotParticle {
        diameter: 1e-3,
        density: 1500.0,
        young: 6e9,
        poisson: 0.3,
    };
    let mut pair = std::mem::MaybeUninit::<DashpotPair>::uninit();
    assert_eq!(
        unsafe { dashpot_pair_spheres(&p, &p, pair.as_mut_ptr()) },
        DashpotStatus::DASHPOT_OK
    );
    unsafe { pair.assume_init() }
}

fn calibrate(reg: *const DashpotRegistry, restitution: f64, contact_time: f64) -> (DashpotStatus, [f64; 2]) {
    let name = CString::new("lsd").unwrap();
    let target = DashpotCalibrationTarget {
        restitution,
        contact_time,
        impact_speed: f64::NAN,
        end_criterion: 1,
    };
    let pair = mcc_pair();
    let mut out = [f64::NAN; 2];
    let mut n_set = 0usize;
    let st = unsafe {
        dashpot_calibrate(
            reg,
            name.as_ptr(),
            &target,
            &pair,
            ptr::null(),
            ptr::null(),
            0,
            out.as_mut_ptr(),
            2,
            &mut n_set,
        )
    };
    (st, out)
}

#[test]
fn a_calibration_whose_stiffness_overflows_is_refused_as_the_cli_refuses_it() {
    let reg = registry();
    // a measurable contact time: k = m (ln²ε + π²)/τ² in closed form
    let (st, out) = calibrate(reg, 0.5, 1e-6);
    assert_eq!(st, DashpotStatus::DASHPOT_OK, "{}", last_error());
    let m = mcc_pair().mass;
    let l = 0.5f64.ln();
    let k = m * (l * l + std::f64::consts::PI.powi(2)) / 1e-12;
    assert!((out[1] / k - 1.0).abs() < 1e-12, "k = {} against {k}", out[1]);
    // τ = 1e-300 s: k overflows to inf, which the C ABI returned as DASHPOT_OK
    let (st, _) = calibrate(reg, 0.5, 1e-300);
    assert_eq!(st, DashpotStatus::DASHPOT_ERR_INVALID_PARAMETER);
    let msg = last_error();
    for needle in ["k = inf", "(0, inf)", "contact time 1e-300 s", "lsd"] {
        assert!(msg.contains(needle), "{needle:?} not in: {msg}");
    }
    unsafe { dashpot_registry_free(reg) };
}

/// LSD with k = 1e308 N/m bound to a pair of mass ~1e-7 kg: √(k/m) overflows, so its damping
/// rate and contact time would be inf and NaN; the binding is refused naming the coefficient and
/// the parameter, and a finite k binds.
#[test]
fn a_law_whose_coefficients_overflow_for_the_pair_is_refused_at_binding() {
    let reg = registry();
    let name = CString::new("lsd").unwrap();
    let key = CString::new("k").unwrap();
    let pair = mcc_pair();
    for (k, ok) in [(1e308, false), (1e6, true)] {
        let (names, values) = ([key.as_ptr()], [k]);
        let mut law: *mut DashpotContactLaw = ptr::null_mut();
        let mut bound: *mut DashpotBoundContact = ptr::null_mut();
        unsafe {
            assert_eq!(
                dashpot_contact_new(reg, name.as_ptr(), names.as_ptr(), values.as_ptr(), 1, &mut law),
                DashpotStatus::DASHPOT_OK,
                "{}",
                last_error()
            );
            let st = dashpot_contact_bind(law, &pair, &mut bound);
            if ok {
                assert_eq!(st, DashpotStatus::DASHPOT_OK, "{}", last_error());
                dashpot_bound_contact_free(bound);
            } else {
                assert_eq!(st, DashpotStatus::DASHPOT_ERR_INVALID_PARAMETER);
                assert!(bound.is_null());
                let msg = last_error();
                for needle in ["k = 1e308", "overflows", "is not finite", "(0, inf)"] {
                    assert!(msg.contains(needle), "{needle:?} not in: {msg}");
                }
            }
            dashpot_contact_free(law);
        }
    }
    unsafe { dashpot_registry_free(reg) };
}

/// A tangential or rolling batch with a zero (or unnormalised) normal is refused naming the
/// contact and its vector; with the unit normal the same batch runs.
#[test]
fn a_normal_that_is_not_a_unit_vector_is_refused() {
    let reg = registry();
    let mut mat = std::mem::MaybeUninit::<DashpotMaterials>::uninit();
    unsafe {
        assert_eq!(
            dashpot_materials_spheres(6e9, 0.3, 6e9, 0.3, mat.as_mut_ptr()),
            DashpotStatus::DASHPOT_OK
        );
    }
    let mat = unsafe { mat.assume_init() };
    let (fnorm, delta, mass, radius) = ([1.0], [1e-6], [1e-6], [5e-4]);
    let velocity = [0.1, 0.0, 0.0];
    for (kind, law) in [("tangential", "mindlin"), ("rolling", "rolling-sds")] {
        for (normal, ok) in [
            ([0.0, 0.0, 1.0], true),
            ([0.0, 0.0, 0.0], false),
            ([0.0, 0.0, 2.0], false),
        ] {
            let name = CString::new(law).unwrap();
            let mut out = [f64::NAN; 3];
            let mut history = [0.0; 16];
            // one batch of one contact through kind's functions (the energy form: one shape)
            macro_rules! batch {
                ($law:ty, $model:ty, $new:ident, $bind:ident, $slots:ident, $call:ident, $free_m:ident, $free_l:ident) => {{
                    let mut l: *mut $law = ptr::null_mut();
                    let mut m: *mut $model = ptr::null_mut();
                    let made = $new(reg, name.as_ptr(), ptr::null(), ptr::null(), 0, &mut l);
                    assert_eq!(made, DashpotStatus::DASHPOT_OK, "{}", last_error());
                    assert_eq!($bind(l, &mat, &mut m), DashpotStatus::DASHPOT_OK);
                    let mut slots = 0usize;
                    $slots(m, &mut slots);
                    let (mut power, mut elastic, mut written) = ([0.0], [0.0], 0);
                    let st = $call(
                        m,
                        1,
                        1e-6,
                        normal.as_ptr(),
                        velocity.as_ptr(),
                        fnorm.as_ptr(),
                        delta.as_ptr(),
                        mass.as_ptr(),
                        radius.as_ptr(),
                        history.as_mut_ptr(),
                        slots,
                        out.as_mut_ptr(),
                        power.as_mut_ptr(),
                        elastic.as_mut_ptr(),
                        &mut written,
                    );
                    $free_m(m);
                    $free_l(l);
                    st
                }};
            }
            let st = unsafe {
                if kind == "tangential" {
                    batch!(
                        DashpotTangentialLaw,
                        DashpotTangentialModel,
                        dashpot_tangential_new,
                        dashpot_tangential_bind_materials,
                        dashpot_tangential_model_history_slots,
                        dashpot_tangential_model_force_batch_energy,
                        dashpot_tangential_model_free,
                        dashpot_tangential_free
                    )
                } else {
                    batch!(
                        DashpotRollingLaw,
                        DashpotRollingModel,
                        dashpot_rolling_new,
                        dashpot_rolling_bind_materials,
                        dashpot_rolling_model_history_slots,
                        dashpot_rolling_model_force_batch,
                        dashpot_rolling_model_free,
                        dashpot_rolling_free
                    )
                }
            };
            if ok {
                assert_eq!(st, DashpotStatus::DASHPOT_OK, "{law}: {}", last_error());
                // a force against the motion, in the tangent plane
                assert!(out[0] < 0.0 && out[2] == 0.0, "{law}: {out:?}");
            } else {
                assert_eq!(
                    st,
                    DashpotStatus::DASHPOT_ERR_INVALID_ARGUMENT,
                    "{law} {normal:?}"
                );
                let msg = last_error();
                assert!(
                    msg.contains("normal of contact 0") && msg.contains("unit vector"),
                    "{law}: {msg}"
                );
            }
        }
    }
    unsafe { dashpot_registry_free(reg) };
}
