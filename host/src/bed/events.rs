//! Event times as roots of quadratics, and the event queue.
//!
//! Every event of the bed (disk–disk, disk–lid, disk–piston on one piston piece, cell crossing)
//! is the first time a *gap* g(τ) = g0 + v τ + ½ a τ² reaches 0 while shrinking. The roots are
//! taken in the cancellation-free form (q = −½(v + sgn(v)√(v² − 2 a g0)), roots q/(a/2) and
//! g0/q), so that a gap that is tiny after a collision gives an accurate tiny root, not 0 ± noise.

/// The first τ ≥ 0 (s) at which the gap g(τ) = g0 + v τ + ½ acc τ² reaches 0 while decreasing.
///
/// A touching or overlapping pair (g0 ≤ 0) that is approaching (v < 0) collides now (τ = 0);
/// a touching pair that is receding (v > 0) does not, and its next contact (if the acceleration
/// brings it back) is the later root. Units: g0 in m, v in m/s, acc in m/s².
#[inline]
pub fn first_contact(g0: f64, v: f64, acc: f64) -> Option<f64> {
    if g0 <= 0.0 && v < 0.0 {
        return Some(0.0);
    }
    let half = 0.5 * acc;
    if half == 0.0 {
        return (v < 0.0).then(|| (-g0 / v).max(0.0));
    }
    let disc = v * v - 4.0 * half * g0;
    if disc < 0.0 {
        return None;
    }
    let q = -0.5 * (v + disc.sqrt().copysign(v));
    if q == 0.0 {
        // g0 = 0 and v = 0: the gap shrinks from now on iff acc < 0.
        return (acc < 0.0).then_some(0.0);
    }
    let (r1, r2) = (q / half, g0 / q);
    let (lo, hi) = if r1 <= r2 { (r1, r2) } else { (r2, r1) };
    [lo, hi].into_iter().find(|&r| r >= 0.0 && v + acc * r < 0.0)
}

/// The first τ ≥ 0 (s) at which two disks at relative position (rx, ry) (m), moving with
/// relative velocity (vx, vy) (m/s) in the same uniform field, are at distance `sigma` (m) while
/// approaching. Touching or overlapping and approaching: 0; receding: never.
#[inline]
pub fn pair_contact(rx: f64, ry: f64, vx: f64, vy: f64, sigma2: f64) -> Option<f64> {
    let b = rx * vx + ry * vy;
    if b >= 0.0 {
        return None;
    }
    let c = rx * rx + ry * ry - sigma2;
    if c <= 0.0 {
        return Some(0.0);
    }
    let vv = vx * vx + vy * vy;
    let disc = b * b - vv * c;
    if disc < 0.0 {
        return None;
    }
    // τ = (−b − √disc)/vv written without cancellation
    Some(c / (-b + disc.sqrt()))
}

/// A tournament (winner) tree over a fixed set of keys: one pending event time per disk.
///
/// Each node holds the (key, index) of the smallest key below it, so a replay reads one small
/// array; `update(i, t)` is O(log N) and stops as soon as a node's winner is unchanged; `top()`
/// is O(1). Ties go to the lower index, so the event order is deterministic.
#[derive(Debug, Clone)]
pub struct Tournament {
    size: usize,
    node: Vec<(f64, u32)>,
}

impl Tournament {
    /// A tree of `n` keys, all +∞.
    pub fn new(n: usize) -> Tournament {
        let size = n.max(1).next_power_of_two();
        let mut node = vec![(f64::INFINITY, 0u32); 2 * size];
        for i in 0..size {
            node[size + i] = (f64::INFINITY, i as u32);
        }
        for k in (1..size).rev() {
            node[k] = node[2 * k];
        }
        Tournament { size, node }
    }

    /// The index with the smallest key, and that key.
    #[inline]
    pub fn top(&self) -> (usize, f64) {
        let (t, i) = self.node[1];
        (i as usize, t)
    }

    /// The key of `i`.
    #[inline]
    pub fn key(&self, i: usize) -> f64 {
        self.node[self.size + i].0
    }

    /// Sets the key of `i` to `t` and replays its path towards the root.
    #[inline]
    pub fn update(&mut self, i: usize, t: f64) {
        let mut k = self.size + i;
        self.node[k].0 = t;
        k >>= 1;
        while k >= 1 {
            let (a, b) = (self.node[2 * k], self.node[2 * k + 1]);
            // ties: the left child holds the lower indices
            let w = if b.0 < a.0 { b } else { a };
            let old = self.node[k];
            if w.1 == old.1 && w.0.to_bits() == old.0.to_bits() {
                break;
            }
            self.node[k] = w;
            k >>= 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiny_gap_gives_an_accurate_tiny_root() {
        // g0 = 1e-12 m closing at 1 m/s under gravity: τ = g0 − 4.9 g0² + ... to full precision
        let t = first_contact(1e-12, -1.0, -9.8).unwrap();
        let exact = 1e-12 - 4.9e-24 - 2.0 * 4.9 * 4.9 * 1e-36;
        assert!((t - exact).abs() < 1e-15 * exact, "{t:e}");
        // a receding touching pair under a restoring acceleration meets again at 2v/|a|
        let t = first_contact(0.0, 2.0, -10.0).unwrap();
        assert!((t - 0.4).abs() < 1e-15);
        let t = first_contact(-1e-18, 2.0, -10.0).unwrap();
        assert!((t - 0.4).abs() < 1e-15);
        // receding and accelerating apart: never
        assert_eq!(first_contact(0.0, 1.0, 3.0), None);
        // approaching and touching: now
        assert_eq!(first_contact(0.0, -1.0, 3.0), Some(0.0));
        // approaching but decelerating to a stop before contact: never
        assert_eq!(first_contact(1.0, -1.0, 1.0), None);
    }

    #[test]
    fn pair_roots_are_cancellation_free() {
        let s2 = 4e-6; // d = 2 mm
                       // head-on at 1 m/s from a gap of 1e-13 m: accurate to the rounding of |r|² (the
                       // textbook root −b − √(b² − v²c) would lose everything below ulp(0.002) ≈ 4e-19 s)
        let t = pair_contact(0.002 + 1e-13, 0.0, -1.0, 0.0, s2).unwrap();
        assert!((t - 1e-13).abs() < 1e-18, "{t:e}");
        // a gap given exactly: r = 1 + 2^-30 against σ = 1 closing at 1 m/s, τ = 2^-30 (1 − 2^-31)
        let t = pair_contact(1.0 + 2f64.powi(-30), 0.0, -1.0, 0.0, 1.0).unwrap();
        assert!((t - 2f64.powi(-30)).abs() < 1e-18, "{t:e}");
        assert_eq!(pair_contact(0.002, 0.0, 1.0, 0.0, s2), None);
        assert_eq!(pair_contact(0.002, 0.0, -1.0, 0.0, s2), Some(0.0));
        // grazing miss
        assert_eq!(pair_contact(0.01, 0.0025, -1.0, 0.0, s2), None);
    }

    #[test]
    fn tournament_tracks_the_minimum_with_ties_to_the_lower_index() {
        let mut t = Tournament::new(5);
        for (i, k) in [3.0, 1.0, 4.0, 1.0, 5.0].into_iter().enumerate() {
            t.update(i, k);
        }
        assert_eq!(t.top(), (1, 1.0));
        t.update(1, 9.0);
        assert_eq!(t.top(), (3, 1.0));
        t.update(3, f64::INFINITY);
        assert_eq!(t.top(), (0, 3.0));
    }
}
