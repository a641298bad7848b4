//! What the plugins' unit tests share (a dev-dependency of the plugins, never linked into one):
//! a head-on collision integrated on a contact law, a tangential or rolling law's batch checked
//! against its per-contact form bit for bit, and the history of a tangential spring.

use dashpot_sdk::{BoundContact, Contact, LawInfo, VectorBatch, VectorContact};

/// One head-on collision integrated by velocity Verlet on the overlap δ (m): impact speed `v0`
/// (m/s), effective mass `mass` (kg), effective radius `radius` (m), step `dt` (s). The law is
/// called once a step at the half-step rate and keeps `history` (as given at first touch, as
/// left at the end). The contact ends when the force returns to 0 on rebound (end criterion
/// `force`). Returns the restitution: the rebound speed over `v0`.
///
/// # Panics
/// When the contact has not ended after 10⁷ steps.
pub fn verlet_rebound(
    law: &impl BoundContact,
    mass: f64,
    radius: f64,
    v0: f64,
    dt: f64,
    history: &mut [f64],
) -> f64 {
    let (mut d, mut u, mut f) = (0.0, v0, 0.0);
    let mut touched = false;
    for _ in 0..10_000_000 {
        d += u * dt - 0.5 * f / mass * dt * dt;
        let u_half = u - 0.5 * f / mass * dt;
        let f_new = law.force(
            Contact {
                delta: d,
                rate: u_half,
                mass,
                radius,
            },
            history,
        );
        u = u_half - 0.5 * f_new / mass * dt;
        f = f_new;
        touched |= f > 0.0;
        if touched && f == 0.0 && u < 0.0 {
            return -u / v0;
        }
    }
    panic!("the contact did not end");
}

/// Runs `contacts` (one time step, that of the first, for all; `slots` history slots each,
/// starting from `history`, `contacts.len() × slots`) one at a time through `force` and as one
/// batch through `force_batch`; asserts that both give the same forces (N) and leave the same
/// history, bit for bit (`what` names the case in a failure), and returns the forces.
pub fn batch_is_per_contact(
    contacts: &[VectorContact],
    history: &[f64],
    slots: usize,
    mut force: impl FnMut(&VectorContact, &mut [f64]) -> [f64; 3],
    force_batch: impl FnOnce(VectorBatch<'_>),
    what: &str,
) -> Vec<[f64; 3]> {
    let n = contacts.len();
    let mut h1 = history.to_vec();
    let f1: Vec<[f64; 3]> = contacts
        .iter()
        .enumerate()
        .map(|(i, c)| force(c, &mut h1[slots * i..slots * (i + 1)]))
        .collect();
    let column = |get: fn(&VectorContact) -> f64| contacts.iter().map(get).collect::<Vec<_>>();
    let normal: Vec<[f64; 3]> = contacts.iter().map(|c| c.normal).collect();
    let velocity: Vec<[f64; 3]> = contacts.iter().map(|c| c.velocity).collect();
    let (normal_force, delta) = (column(|c| c.normal_force), column(|c| c.delta));
    let (mass, radius) = (column(|c| c.mass), column(|c| c.radius));
    let (mut h2, mut f2) = (history.to_vec(), vec![[0.0; 3]; n]);
    force_batch(VectorBatch {
        dt: contacts[0].dt,
        normal: &normal,
        velocity: &velocity,
        normal_force: &normal_force,
        delta: &delta,
        mass: &mass,
        radius: &radius,
        slots,
        history: &mut h2,
        force: &mut f2,
    });
    for i in 0..n {
        for k in 0..3 {
            assert_eq!(f1[i][k].to_bits(), f2[i][k].to_bits(), "force {i}.{k}, {what}");
        }
        for k in slots * i..slots * (i + 1) {
            assert_eq!(h1[k].to_bits(), h2[k].to_bits(), "history slot {k}, {what}");
        }
    }
    f1
}

/// Asserts that a law's `info` declares the history of a tangential spring: the three
/// components `xi_x`, `xi_y`, `xi_z` of its displacement ξ (m).
pub fn assert_spring_history(info: &LawInfo) {
    let slots: Vec<(&str, &str)> = info
        .history
        .iter()
        .map(|h| (h.name.as_str(), h.unit.as_str()))
        .collect();
    assert_eq!(
        slots,
        [("xi_x", "m"), ("xi_y", "m"), ("xi_z", "m")],
        "{}",
        info.name
    );
}
