//! What a contact's normal law tells the other laws of that contact (sdk 0.4): its contact
//! radius, the force their Coulomb-type caps scale with, and its damping coefficient.
//!
//! Coupled contact models need these from the normal law: LAMMPS's tangential damping is a
//! multiple of the normal damping prefactor, every friction, rolling and twisting cap uses the
//! normal model's critical force (|F_n|, or |F_ne + 2 F_pulloff| for adhesive models), Mindlin's
//! and Marshall's stiffnesses use the contact radius a (JKR's own a), and so does heat
//! conduction. A normal law reports one [`NormalContext`] per contact
//! ([`BoundContact::context`](crate::BoundContact::context)); a tangential, rolling, twisting or
//! heat law that declares `READS_CONTEXT` receives it in its contact's `context` field.

use abi_stable::StableAbi;

/// What a contact's normal law tells the other families of that contact (sdk 0.4).
///
/// Units are those of the caller's system (SI in dashpot's own hosts; any consistent units,
/// LAMMPS's lj included, in a host that passes them through).
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy, PartialEq, Default)]
pub struct NormalContext {
    /// Contact radius a (m), ≥ 0: the radius of the contact disc (JKR: positive past touching,
    /// until rupture).
    pub contact_radius: f64,
    /// The force the Coulomb-type caps of the other families scale with, F_c (N), ≥ 0 (LAMMPS's
    /// Fncrit): friction is capped at μ F_c, rolling and twisting resistance likewise.
    pub cap_force: f64,
    /// Normal damping coefficient η_n (N·s/m), ≥ 0 (LAMMPS's damp_prefactor): the normal law's
    /// dissipative force is −η_n times the normal relative velocity.
    pub damping: f64,
}

impl NormalContext {
    /// The context of a normal law that reports none of its own (every law of sdk 0.1–0.3, and
    /// a law of sdk 0.4 that keeps the default), from the effective radius R (m), the overlap δ
    /// (m) and the normal force F_n (N): the Hertzian contact radius a = √(R max(δ, 0))
    /// ([`physics::contact_radius`](crate::physics::contact_radius)), the cap force max(F_n, 0)
    /// and no damping. What a motion or heat batch without contexts gives its laws.
    #[inline(always)]
    pub fn hertzian(radius: f64, delta: f64, force: f64) -> NormalContext {
        NormalContext {
            contact_radius: (radius * delta.max(0.0)).sqrt(),
            cap_force: force.max(0.0),
            damping: 0.0,
        }
    }

    /// Whether every field is finite and ≥ 0 (what a host and the sdk check).
    #[inline(always)]
    pub fn is_valid(&self) -> bool {
        let ok = |x: f64| (0.0..f64::INFINITY).contains(&x);
        ok(self.contact_radius) & ok(self.cap_force) & ok(self.damping)
    }

    /// The three fields as `[contact_radius, cap_force, damping]` (the C ABI's layout of one
    /// contact's context).
    #[inline(always)]
    pub fn to_array(self) -> [f64; 3] {
        [self.contact_radius, self.cap_force, self.damping]
    }
}
