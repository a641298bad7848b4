//! The documentation of the `gran-*` laws (`dashpot law NAME`), as macros expanding to string
//! literals, so that each law's `DOC` is one constant assembled from its parts.

/// The text every normal law ends with.
macro_rules! normal_common_doc {
    () => {
        " Total normal force F_n = F_ne + η_n δ̇ (N, > 0 repulsive), δ̇ > 0 while approaching \
        (LAMMPS's −v_n); with `limit_damping` = 1 (where offered) a negative F_n is clamped to 0, \
        no attraction on rebound. The contact acts while δ > 0 (JKR: from touch to its pull-off \
        distance). To the other laws of the contact the law reports (sdk 0.4 normal context) the \
        contact radius a (m), the damping prefactor η_n (N·s/m; LAMMPS's tangential dashpot is \
        x_t η_n) and the cap force F_c (N; LAMMPS's Fncrit: |F_n|, or |F_ne + 2 F_po| for DMT and \
        JKR), exactly as LAMMPS's sub-models read contact_radius, damp_prefactor and Fncrit. \
        Energy: elastic ∫F_ne dδ from the end of contact (J); power (F_n − F_ne) δ̇ ≥ 0 (W). \
        Same forces as LAMMPS 22 Jul 2025 (`pair_style granular`, `fix wall/gran`) to rounding, \
        step by step, when the host passes LAMMPS's geometry (docs/laws.md). Any consistent \
        units (LAMMPS's lj too): the parameters' ranges are signs and physical bounds only; \
        units are named in SI. References: LAMMPS pair_style granular documentation; Luding, \
        Granular Matter 10, 235 (2008)."
    };
}
pub(crate) use normal_common_doc;

/// `hooke`.
macro_rules! hooke_doc {
    () => {
        "LAMMPS `pair_style granular` normal model `hooke k damp`: elastic force F_ne = k δ \
        (N) at overlap δ (m), k (N/m) the parameter `k` (required)."
    };
}
pub(crate) use hooke_doc;

/// `hertz`.
macro_rules! hertz_doc {
    () => {
        "LAMMPS `pair_style granular` normal model `hertz k damp`: elastic force F_ne = k a δ \
        (N), a = √(δ R) the contact radius (m), R the effective radius, k (N/m², LAMMPS's \
        force/area) the parameter `k` (required). Classic `gran/hertz/history kn ...` is this \
        with k = kn (converted by LAMMPS from pressure units: kn/nktv2p)."
    };
}
pub(crate) use hertz_doc;

/// `hertz/material`.
macro_rules! hertz_material_doc {
    () => {
        "LAMMPS `pair_style granular` normal model `hertz/material E damp ν`: elastic force \
        F_ne = (4/3) E_eff a δ (N), a = √(δ R) (m), E_eff the bound materials' effective Young's \
        modulus (Pa). LAMMPS mixes 1/E_eff = (1 − ν1²)/E1 + (1 − ν2²)/E2 and takes a wall of the \
        particle's own material, E_eff = E/(2(1 − ν²)): the host binds the law to those moduli \
        (E and ν are not parameters here; `damp` is)."
    };
}
pub(crate) use hertz_material_doc;

/// `dmt`.
macro_rules! dmt_doc {
    () => {
        "LAMMPS `pair_style granular` normal model `dmt E damp ν γ` (Derjaguin, Muller & \
        Toporov, J. Colloid Interface Sci. 53, 314, 1975): F_ne = (4/3) E_eff a δ − F_po (N), \
        a = √(δ R), F_po = 4π γ R the pull-off force, while δ > 0; γ (J/m², LAMMPS's `cohesion`) \
        the parameter `cohesion` (required). E_eff from the bound materials as for \
        hertz/material. Cap force F_c = |F_ne + 2 F_po|. LAMMPS refuses `tsuji`, \
        `coeff_restitution` and `limit_damping` with it."
    };
}
pub(crate) use dmt_doc;

/// `jkr`.
macro_rules! jkr_doc {
    () => {
        "LAMMPS `pair_style granular` normal model `jkr E damp ν γ` (Johnson, Kendall & \
        Roberts, Proc. R. Soc. Lond. A 324, 301, 1971): F_ne = (4 E_eff/(3R)) a³ − \
        2π a² √(4 γ E_eff/(π a)) (N), a the JKR contact radius of δ = a²/R − 2 √(π γ a/E_eff) \
        (LAMMPS's closed-form root), γ (J/m², LAMMPS's `cohesion`, half the work of adhesion \
        w = 2γ) the parameter `cohesion` (required). The contact forms at touch (δ > 0), acts in \
        tension beyond it and breaks at LAMMPS's pull-off distance δ_po = (3π²/16)^{1/3} \
        (R γ²/E_eff²)^{1/3} (its reach), where the force is its largest tension −3π γ R = \
        −(3/2) π w R (load-controlled pull-off; dashpot's own `jkr` breaks later, at the \
        displacement-controlled rupture). History `touch` (1 while the contact acts). Elastic energy \
        measured from touch: at the pull-off distance the contact holds its cycle's adhesion \
        hysteresis, lost (booked dissipated) as it ends. Cap force \
        F_c = |F_ne + 2 F_po|, F_po = 3π γ R. LAMMPS refuses `tsuji`, `coeff_restitution` and \
        `limit_damping` with it."
    };
}
pub(crate) use jkr_doc;

/// `damping velocity`.
macro_rules! velocity_doc {
    () => {
        " Damping `velocity`: η_n = damp (N·s/m)."
    };
}
pub(crate) use velocity_doc;

/// `damping mass_velocity`.
macro_rules! mass_velocity_doc {
    () => {
        " Damping `mass_velocity`: η_n = damp m (damp in 1/s, m the effective mass). With \
        hooke: a linear oscillator of restitution exp(−π ζ/√(1 − ζ²)), ζ = damp/(2√(k/m)) \
        (classic `gran/hooke` and `gran/hooke/history`: damp = gamman)."
    };
}
pub(crate) use mass_velocity_doc;

/// `damping viscoelastic`.
macro_rules! viscoelastic_doc {
    () => {
        " Damping `viscoelastic` (LAMMPS's default): η_n = damp m a (damp in 1/(m·s)) \
        (classic `gran/hertz/history`: damp = gamman)."
    };
}
pub(crate) use viscoelastic_doc;

/// `damping tsuji`.
macro_rules! tsuji_doc {
    () => {
        " Damping `tsuji`: η_n = α(e) √(m F_ne/δ), α(e) = 1.2728 − 4.2783 e + 11.087 e² − \
        22.348 e³ + 27.467 e⁴ − 18.022 e⁵ + 4.8218 e⁶ (Marshall, J. Comput. Phys. 228, 1541, \
        2009, eq. 53: a fit to Tsuji, Tanaka & Ishida, Powder Technol. 71, 239, 1992), damp = e \
        the restitution, in [0, 1]."
    };
}
pub(crate) use tsuji_doc;

/// `damping coeff_restitution`.
macro_rules! coeff_restitution_doc {
    () => {
        " Damping `coeff_restitution`: η_n = β(e) √(m F_ne/δ), damp = e the restitution in \
        (0, 1]; β = −2 ln e/√(π² + ln² e) for hooke (η_n = 2ζ√(m k)) and \
        −√5 ln e/√(π² + ln² e) for the Hertzian models (Antypov & Elliott, EPL 94, 50004, \
        2011, eq. 17): the restitution is e at every impact speed when the contact ends as δ \
        returns to 0."
    };
}
pub(crate) use coeff_restitution_doc;
