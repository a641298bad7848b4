//! Tangential (friction) laws (sdk 0.2, 0.3): the tangential force on every contact with its
//! history, and sdk 0.3's energy outputs. (Creating, binding and freeing: `kinds.rs`.)
//!
//! Vectors are `[x, y, z]` triples stored one after the other (`3 n` doubles for `n` contacts;
//! a 2D code sets z = 0). `normal[i]` is the unit normal from the partner j to the particle i the
//! force acts on; `velocity[i]` the relative velocity of i's contact point with respect to j's
//! (ω × r terms included; the law uses its part in the tangent plane); the result is the
//! tangential force on i (N), capped by Coulomb's μ F_n. History (a spring's displacement, for
//! example) is stored by the caller exactly as for contact laws: zero at first touch, updated in
//! place by each call, kept when the step is accepted, dropped when the contact ends.

use crate::error::DashpotStatus;
use crate::handle::energy_batch;
use crate::kinds::DashpotTangentialModel;

/// The tangential force on `n` contacts, history advanced by the time step `dt` (s).
///
/// Per contact i: `normal[3i..3i+3]` the unit normal (from partner to particle),
/// `velocity[3i..3i+3]` the relative contact-point velocity (m/s), `normal_force[i]` the normal
/// force this step (N, > 0 repulsive; from the normal law), `delta[i]` the overlap (m),
/// `mass[i]`, `radius[i]` the effective mass (kg) and radius (m), `history[i*slots ..]` its
/// history (`n_history = n × slots` values, read and updated in place) and
/// `out_force[3i..3i+3]` the tangential force on the particle (N).
///
/// Every input is checked inside the plugin, as for `dashpot_contact_model_force_batch` (a
/// non-finite vector, normal force or `dt` too), and so are its errors, ownership and thread
/// safety.
///
/// # Safety
/// As `dashpot_contact_model_force_batch`'s, with `3n` values in each vector array.
#[allow(clippy::too_many_arguments)]
#[no_mangle]
pub unsafe extern "C" fn dashpot_tangential_model_force_batch(
    model: *const DashpotTangentialModel,
    n: usize,
    dt: f64,
    normal: *const f64,
    velocity: *const f64,
    normal_force: *const f64,
    delta: *const f64,
    mass: *const f64,
    radius: *const f64,
    history: *mut f64,
    n_history: usize,
    out_force: *mut f64,
) -> DashpotStatus {
    // the energy batch's body, without the energy outputs
    let (null, what) = (std::ptr::null_mut(), "dashpot_tangential_model_force_batch");
    let arrays = [normal_force, delta, mass, radius];
    let names = ["velocity", "out_force"];
    unsafe {
        energy_batch(
            what,
            names,
            model,
            n,
            dt,
            normal,
            velocity,
            arrays,
            history,
            n_history,
            out_force,
            [null; 2],
            null.cast(),
        )
    }
}
