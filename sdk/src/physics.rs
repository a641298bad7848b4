//! Formulas several laws share, each with its source.

use std::f64::consts::PI;

/// The exact Tsuji damping factor α(ε) = −√5 ln ε / √(ln²ε + π²) of the Hertzian
/// spring-dashpot that realizes restitution ε when contact ends as δ returns to 0 (Antypov &
/// Elliott 2011, eq. 17). Dimensionless; α(1) = 0.
pub fn tsuji_alpha(eps: f64) -> f64 {
    let l = eps.ln();
    -(5.0f64).sqrt() * l / (l * l + PI * PI).sqrt()
}

/// The damping ratio ζ = −ln ε / √(ln²ε + π²) of the linear spring-dashpot with restitution ε
/// (Antypov & Elliott 2011, eq. 8: γ = ζ ω0). Dimensionless.
pub fn lsd_damping_ratio(eps: f64) -> f64 {
    let l = eps.ln();
    -l / (l * l + PI * PI).sqrt()
}

/// Hertz contact radius a = √(r δ) (m) at overlap δ (m) for effective radius r (m); 0 for δ ≤ 0.
#[inline]
pub fn contact_radius(radius: f64, delta: f64) -> f64 {
    (radius * delta.max(0.0)).sqrt()
}

/// Thornton's (1997) restitution of elastic–perfectly plastic spheres at x = V_y/v (V_y the
/// yield impact speed, v the normal impact speed): 1 for x ≥ 1 (an elastic impact), else
/// e = √(6√3/5) √(1 − x²/6) (x / (x + 2 √(6/5 − x²/5)))^{1/4}, which falls as v^{−1/4} far above
/// V_y. Dimensionless.
pub fn thornton_restitution(x: f64) -> f64 {
    if x >= 1.0 {
        return 1.0;
    }
    (6.0 * 3f64.sqrt() / 5.0).sqrt()
        * (1.0 - x * x / 6.0).sqrt()
        * (x / (x + 2.0 * (1.2 - 0.2 * x * x).sqrt())).powf(0.25)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn damping_factors_vanish_for_elastic_and_relate_by_sqrt5() {
        assert_eq!(tsuji_alpha(1.0), 0.0);
        assert_eq!(lsd_damping_ratio(1.0), 0.0);
        for eps in [0.1, 0.5, 0.9] {
            let r = tsuji_alpha(eps) / lsd_damping_ratio(eps);
            assert!((r - 5f64.sqrt()).abs() < 1e-14, "{eps}: {r}");
        }
    }
}
