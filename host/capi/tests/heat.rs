//! The heat kind through the C ABI (sdk 0.4): a heat law made by name, bound to materials, and
//! its batch call: LAMMPS's `heat radius` and `heat area` conductances, Q_ji = −Q_ij to the bit,
//! the normal law's contexts or the defaults, and every bad argument an error naming it.

use dashpot_capi::*;
use std::ffi::CString;
use std::ptr;

mod common;
use common::{deps_dir, last_error};

/// Heat law `name` with its one coefficient `p` = `v`, bound to steel on steel.
unsafe fn model(reg: *const DashpotRegistry, name: &str, p: &str, v: f64) -> *mut DashpotHeatModel {
    let (name, p) = (CString::new(name).unwrap(), CString::new(p).unwrap());
    let (names, values) = ([p.as_ptr()], [v]);
    let mut law: *mut DashpotHeatLaw = ptr::null_mut();
    let mut mat = std::mem::MaybeUninit::<DashpotMaterials>::uninit();
    let mut m: *mut DashpotHeatModel = ptr::null_mut();
    unsafe {
        assert_eq!(
            dashpot_heat_new(reg, name.as_ptr(), names.as_ptr(), values.as_ptr(), 1, &mut law),
            DashpotStatus::DASHPOT_OK,
            "{}",
            last_error()
        );
        assert_eq!(
            dashpot_materials_spheres(2.0e11, 0.3, 2.0e11, 0.3, mat.as_mut_ptr()),
            DashpotStatus::DASHPOT_OK
        );
        assert_eq!(
            dashpot_heat_bind_materials(law, mat.as_ptr(), &mut m),
            DashpotStatus::DASHPOT_OK,
            "{}",
            last_error()
        );
        dashpot_heat_free(law);
    }
    m
}

#[test]
fn the_heat_batch_conducts_as_lammps_radius_and_area_models() {
    let dir = deps_dir();
    let dirs = [dir.as_ptr()];
    let mut reg: *mut DashpotRegistry = ptr::null_mut();
    unsafe {
        assert_eq!(
            dashpot_registry_open(dirs.as_ptr(), 1, 0, &mut reg),
            DashpotStatus::DASHPOT_OK
        );
        let (k, h) = (2.0, 5.0e4);
        let radius_law = model(reg, "heat-radius", "k", k);
        let area_law = model(reg, "heat-area", "h", h);
        let mut reads = 0;
        assert_eq!(
            dashpot_heat_model_reads_context(radius_law, &mut reads),
            DashpotStatus::DASHPOT_OK
        );
        assert_eq!(reads, 1);
        let mut slots = 7;
        assert_eq!(
            dashpot_heat_model_history_slots(radius_law, &mut slots),
            DashpotStatus::DASHPOT_OK
        );
        assert_eq!(slots, 0);

        // the two orders of one contact, and a contact apart
        let t = [300.0, 350.0, 350.0, 300.0, 300.0, 400.0];
        let (fnorm, delta, r) = ([1.0, 1.0, 0.0], [1e-6, 1e-6, -1e-7], [5e-4, 5e-4, 5e-4]);
        let (mut q, mut g) = ([0.0; 3], [0.0; 3]);
        let a = (5e-4f64 * 1e-6).sqrt();
        for (m, want) in [
            (radius_law, 2.0 * k * a),
            (area_law, h * std::f64::consts::PI * a * a),
        ] {
            let st = dashpot_heat_model_heat_batch(
                m,
                3,
                1e-5,
                t.as_ptr(),
                fnorm.as_ptr(),
                delta.as_ptr(),
                r.as_ptr(),
                ptr::null(),
                ptr::null_mut(),
                0,
                q.as_mut_ptr(),
                g.as_mut_ptr(),
            );
            assert_eq!(st, DashpotStatus::DASHPOT_OK, "{}", last_error());
            assert_eq!(g[0], want);
            assert_eq!(q[0], want * 50.0);
            assert_eq!(q[1].to_bits(), (-q[0]).to_bits());
            assert_eq!((q[2], g[2]), (0.0, 0.0));
        }

        // the normal law's context: its contact radius, 3 doubles per contact
        let ctx = [1e-4, 1.0, 0.0, 1e-4, 1.0, 0.0, 0.0, 0.0, 0.0];
        let st = dashpot_heat_model_heat_batch(
            radius_law,
            3,
            1e-5,
            t.as_ptr(),
            fnorm.as_ptr(),
            delta.as_ptr(),
            r.as_ptr(),
            ctx.as_ptr(),
            ptr::null_mut(),
            0,
            q.as_mut_ptr(),
            ptr::null_mut(),
        );
        assert_eq!(st, DashpotStatus::DASHPOT_OK, "{}", last_error());
        assert_eq!(q[0], 2.0 * k * 1e-4 * 50.0);

        // bad arguments, each named
        let call = |m: *const DashpotHeatModel, t: &[f64], n_history: usize, out: *mut f64| {
            let mut q = [0.0; 3];
            let out = if out.is_null() { out } else { q.as_mut_ptr() };
            dashpot_heat_model_heat_batch(
                m,
                3,
                1e-5,
                t.as_ptr(),
                fnorm.as_ptr(),
                delta.as_ptr(),
                r.as_ptr(),
                ptr::null(),
                ptr::null_mut(),
                n_history,
                out,
                ptr::null_mut(),
            )
        };
        let mut sink = 0.0;
        assert_eq!(
            call(ptr::null(), &t, 0, &mut sink),
            DashpotStatus::DASHPOT_ERR_NULL_POINTER
        );
        assert!(last_error().contains("model"), "{}", last_error());
        assert_eq!(
            call(radius_law, &t, 0, ptr::null_mut()),
            DashpotStatus::DASHPOT_ERR_NULL_POINTER
        );
        assert!(last_error().contains("out_heat"), "{}", last_error());
        assert_eq!(
            call(radius_law, &t, 2, &mut sink),
            DashpotStatus::DASHPOT_ERR_BAD_LENGTH
        );
        assert!(last_error().contains("history"), "{}", last_error());
        let mut bad = t;
        bad[3] = f64::NAN;
        assert_eq!(
            call(radius_law, &bad, 0, &mut sink),
            DashpotStatus::DASHPOT_ERR_NON_FINITE
        );
        assert!(last_error().contains("temperature[1]"), "{}", last_error());

        dashpot_heat_model_free(radius_law);
        dashpot_heat_model_free(area_law);
        dashpot_registry_free(reg);
    }
}
