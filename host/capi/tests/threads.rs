//! The header's thread rules, exercised through the exported functions: one bound law evaluated
//! from several threads at once gives every thread the same forces, and each thread sees its
//! own last-error message.

use dashpot_capi::*;
use std::ffi::CString;
use std::ptr;

mod common;
use common::{deps_dir, last_error};

/// A pointer that may cross threads (the header promises the handle may).
struct Shared<T>(*const T);
impl<T> Clone for Shared<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for Shared<T> {}
unsafe impl<T> Send for Shared<T> {}
unsafe impl<T> Sync for Shared<T> {}

#[test]
fn one_bound_law_serves_many_threads_and_errors_stay_per_thread() {
    let dir = deps_dir();
    let dirs = [dir.as_ptr()];
    let mut reg: *mut DashpotRegistry = ptr::null_mut();
    let mut law: *mut DashpotContactLaw = ptr::null_mut();
    let mut bound: *mut DashpotBoundContact = ptr::null_mut();
    let eps = CString::new("eps").unwrap();
    let names = [eps.as_ptr()];
    let values = [0.54];
    let mcc = DashpotParticle {
        diameter: 0.01,
        density: 1500.0,
        young: 6.0e9,
        poisson: 0.3,
    };
    let mut pair = DashpotPair {
        mass: 0.0,
        radius: 0.0,
        young: 0.0,
    };
    unsafe {
        assert_eq!(
            dashpot_registry_open(dirs.as_ptr(), 1, 0, &mut reg),
            DashpotStatus::DASHPOT_OK
        );
        let hsd = CString::new("hsd").unwrap();
        assert_eq!(
            dashpot_contact_new(reg, hsd.as_ptr(), names.as_ptr(), values.as_ptr(), 1, &mut law),
            DashpotStatus::DASHPOT_OK
        );
        assert_eq!(
            dashpot_pair_spheres(&mcc, &mcc, &mut pair),
            DashpotStatus::DASHPOT_OK
        );
        assert_eq!(
            dashpot_contact_bind(law, &pair, &mut bound),
            DashpotStatus::DASHPOT_OK
        );
    }
    let n = 10_000;
    let delta: Vec<f64> = (0..n).map(|i| 1e-7 * i as f64).collect();
    let rate: Vec<f64> = (0..n).map(|i| (i as f64 / n as f64) - 0.5).collect();
    let mut expected = vec![0.0; n];
    let st = unsafe {
        dashpot_contact_force_batch(
            bound,
            delta.as_ptr(),
            n,
            rate.as_ptr(),
            n,
            expected.as_mut_ptr(),
            n,
        )
    };
    assert_eq!(st, DashpotStatus::DASHPOT_OK);

    let b = Shared(bound as *const DashpotBoundContact);
    let r = Shared(reg as *const DashpotRegistry);
    std::thread::scope(|s| {
        for t in 0..4 {
            let (delta, rate, expected) = (&delta, &rate, &expected);
            s.spawn(move || {
                let (b, r) = (b, r);
                for _ in 0..50 {
                    let mut out = vec![0.0; n];
                    let st = unsafe {
                        dashpot_contact_force_batch(
                            b.0,
                            delta.as_ptr(),
                            n,
                            rate.as_ptr(),
                            n,
                            out.as_mut_ptr(),
                            n,
                        )
                    };
                    assert_eq!(st, DashpotStatus::DASHPOT_OK);
                    assert_eq!(&out, expected);
                }
                // each thread fails with its own law name and reads back its own message
                let name = CString::new(format!("no-such-law-{t}")).unwrap();
                let mut idx = 0usize;
                let st = unsafe { dashpot_registry_find(r.0, name.as_ptr(), &mut idx) };
                assert_eq!(st, DashpotStatus::DASHPOT_ERR_UNKNOWN_LAW);
                std::thread::yield_now();
                let msg = last_error();
                assert!(msg.contains(&format!("'no-such-law-{t}'")), "thread {t}: {msg}");
            });
        }
    });
    unsafe {
        dashpot_bound_contact_free(bound);
        dashpot_contact_free(law);
        dashpot_registry_free(reg);
    }
}
