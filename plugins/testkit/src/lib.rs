//! What the plugins' unit tests share (a dev-dependency of the plugins, never linked into one):
//! a head-on collision integrated on a contact law, a tangential or rolling law's batch checked
//! against its per-contact form bit for bit, the history of a tangential spring, and the
//! inputs of such checks (a steel bead, uniform random numbers).

use dashpot_sdk::{
    BoundContact, Contact, Energy, EnergyBatch, LawInfo, Particle, VectorBatch, VectorContact,
};

/// A steel bead of 6 mm diameter (m), 7800 kg/m³, E = 200 GPa, ν = 0.3.
pub const STEEL_6MM: Particle = Particle {
    diameter: 0.006,
    density: 7800.0,
    young: 2.0e11,
    poisson: 0.3,
};

/// Uniform numbers in [0, 1) from a xorshift64 generator (Marsaglia 2003) started at `seed`
/// (not 0): the same sequence on every machine, so a failing case can be replayed.
pub fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}

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

/// The arrays of a batch of `contacts`.
struct Columns {
    normal: Vec<[f64; 3]>,
    velocity: Vec<[f64; 3]>,
    normal_force: Vec<f64>,
    delta: Vec<f64>,
    mass: Vec<f64>,
    radius: Vec<f64>,
    context: Vec<dashpot_sdk::NormalContext>,
    dt: f64,
}

impl Columns {
    fn of(contacts: &[VectorContact]) -> Columns {
        let column = |get: fn(&VectorContact) -> f64| contacts.iter().map(get).collect::<Vec<_>>();
        Columns {
            normal: contacts.iter().map(|c| c.normal).collect(),
            velocity: contacts.iter().map(|c| c.velocity).collect(),
            normal_force: column(|c| c.normal_force),
            delta: column(|c| c.delta),
            mass: column(|c| c.mass),
            radius: column(|c| c.radius),
            context: contacts.iter().map(|c| c.context).collect(),
            dt: contacts[0].dt,
        }
    }

    fn batch<'a>(
        &'a self,
        slots: usize,
        history: &'a mut [f64],
        force: &'a mut [[f64; 3]],
    ) -> VectorBatch<'a> {
        VectorBatch {
            dt: self.dt,
            normal: &self.normal,
            velocity: &self.velocity,
            normal_force: &self.normal_force,
            delta: &self.delta,
            mass: &self.mass,
            radius: &self.radius,
            context: &self.context,
            slots,
            history,
            force,
        }
    }
}

/// Asserts that two runs gave the same forces and histories, bit for bit.
fn same_bits(f: [&[[f64; 3]]; 2], h: [&[f64]; 2], what: &str) {
    for (i, (a, b)) in f[0].iter().zip(f[1]).enumerate() {
        assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits), "force {i}, {what}");
    }
    for (k, (a, b)) in h[0].iter().zip(h[1]).enumerate() {
        assert_eq!(a.to_bits(), b.to_bits(), "history slot {k}, {what}");
    }
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
    let mut h1 = history.to_vec();
    let f1: Vec<[f64; 3]> = contacts
        .iter()
        .enumerate()
        .map(|(i, c)| force(c, &mut h1[slots * i..slots * (i + 1)]))
        .collect();
    let cols = Columns::of(contacts);
    let (mut h2, mut f2) = (history.to_vec(), vec![[0.0; 3]; contacts.len()]);
    force_batch(cols.batch(slots, &mut h2, &mut f2));
    same_bits([&f1, &f2], [&h1, &h2], what);
    f1
}

/// [`batch_is_per_contact`] with the energy outputs: `contacts` one at a time through
/// `force_energy` and as one batch through `force_batch_energy` give the same forces, histories,
/// powers (W) and elastic energies (J), bit for bit, and every contact reports its energy.
pub fn batch_energy_is_per_contact(
    contacts: &[VectorContact],
    history: &[f64],
    slots: usize,
    mut force_energy: impl FnMut(&VectorContact, &mut [f64]) -> ([f64; 3], Option<Energy>),
    force_batch_energy: impl FnOnce(VectorBatch<'_>, EnergyBatch<'_>) -> bool,
    what: &str,
) {
    let n = contacts.len();
    let mut h1 = history.to_vec();
    let (f1, e1): (Vec<[f64; 3]>, Vec<Energy>) = contacts
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let (f, e) = force_energy(c, &mut h1[slots * i..slots * (i + 1)]);
            (f, e.expect("the law reports its energy"))
        })
        .unzip();
    let cols = Columns::of(contacts);
    let (mut h2, mut f2) = (history.to_vec(), vec![[0.0; 3]; n]);
    let (mut power, mut elastic) = (vec![0.0; n], vec![0.0; n]);
    let out = EnergyBatch {
        power: &mut power,
        elastic: &mut elastic,
    };
    assert!(
        force_batch_energy(cols.batch(slots, &mut h2, &mut f2), out),
        "{what}"
    );
    same_bits([&f1, &f2], [&h1, &h2], what);
    for (i, e) in e1.iter().enumerate() {
        assert_eq!(e.power.to_bits(), power[i].to_bits(), "power {i}, {what}");
        assert_eq!(e.elastic.to_bits(), elastic[i].to_bits(), "elastic {i}, {what}");
    }
}

/// Asserts that a law's `info` declares the history of a tangential spring first: the three
/// components `xi_x`, `xi_y`, `xi_z` of its displacement ξ (m).
pub fn assert_spring_history(info: &LawInfo) {
    let slots: Vec<(&str, &str)> = info.history[..3.min(info.history.len())]
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
