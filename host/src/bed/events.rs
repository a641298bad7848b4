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
/// brings it back) is the later root, as if g0 were 0 (an overlap here is roundoff: an
/// accelerated pair that seemed to stay overlapping would otherwise never collide again and
/// would pass through each other). At rest and pressed together (v = 0, acc < 0): now. Units: g0 in m, v in m/s, acc in m/s².
#[inline]
pub fn first_contact(g0: f64, v: f64, acc: f64) -> Option<f64> {
    if g0 <= 0.0 && v < 0.0 {
        return Some(0.0);
    }
    // a touching pair whose gap is negative by roundoff counts as touching: otherwise a pair
    // pressed together (acc < 0) whose gap never climbs back above 0 would never be found again
    let g0 = g0.max(0.0);
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
    pair_contact_before(rx, ry, vx, vy, sigma2, f64::INFINITY)
}

/// [`pair_contact`], but only if the contact comes before `before` (s): a pair that cannot meet
/// that soon is rejected without a square root, since τ ≥ c/(−2b) (the prediction of a disk
/// only needs contacts earlier than the best event it has found so far).
#[inline]
pub fn pair_contact_before(rx: f64, ry: f64, vx: f64, vy: f64, sigma2: f64, before: f64) -> Option<f64> {
    let b = rx * vx + ry * vy;
    if b >= 0.0 {
        return None;
    }
    let c = rx * rx + ry * ry - sigma2;
    if c <= 0.0 {
        return Some(0.0);
    }
    if c >= -2.0 * b * before {
        return None;
    }
    let vv = vx * vx + vy * vy;
    let disc = b * b - vv * c;
    if disc < 0.0 {
        return None;
    }
    // τ = (−b − √disc)/vv written without cancellation
    Some(c / (-b + disc.sqrt()))
}

/// The first τ in [0, `horizon`] (s) at which two disks at relative position (rx, ry) (m), with
/// relative velocity (vx, vy) (m/s) and relative vertical acceleration `ay` (m/s²) (one disk
/// rides on the piston, the other flies under gravity), are at distance √`sigma2` while
/// approaching. The squared distance minus σ² is a quartic in τ; its sign changes are isolated
/// between the roots of its derivatives (down to a quadratic, solved in closed form), so no
/// contact is missed however briefly the disks touch. Touching (or overlapping by roundoff) and
/// approaching, or at rest and accelerating into each other: 0.
pub fn accel_pair_contact(
    rx: f64,
    ry: f64,
    vx: f64,
    vy: f64,
    ay: f64,
    sigma2: f64,
    horizon: f64,
) -> Option<f64> {
    let h = 0.5 * ay;
    let c0 = rx * rx + ry * ry - sigma2;
    let c1 = 2.0 * (rx * vx + ry * vy);
    let c2 = vx * vx + vy * vy + 2.0 * ry * h;
    let (c3, c4) = (2.0 * vy * h, h * h);
    if c0 <= 0.0 && (c1 < 0.0 || (c1 == 0.0 && c2 < 0.0)) {
        return Some(0.0);
    }
    if horizon.is_nan() || horizon <= 0.0 {
        return None;
    }
    let hi = horizon.min(1e300);
    // exact distance at τ, for the refinement (no cancellation in expanded coefficients)
    let f = |t: f64| {
        let dx = rx + vx * t;
        let dy = ry + (vy + h * t) * t;
        dx * dx + dy * dy - sigma2
    };
    let roots = if c0 <= 0.0 {
        // touching and receding: the roots of f/τ (a cubic) are the later contacts
        let cubic = [c1, c2, c3, c4];
        poly_roots(&cubic, 0.0, hi, &|t| horner(&cubic, t))
    } else {
        poly_roots(&[c0, c1, c2, c3, c4], 0.0, hi, &f)
    };
    // f starts positive (or touching and receding): its first sign change is a contact
    roots.into_iter().next()
}

/// p(τ) = Σ c_k τ^k.
#[inline]
fn horner(c: &[f64], t: f64) -> f64 {
    c.iter().rev().fold(0.0, |a, &k| a * t + k)
}

/// The points in (lo, hi] where the polynomial `c` (ascending coefficients) changes sign (or
/// is exactly 0), ascending; `eval` evaluates it (or a function of the same sign that is more
/// accurate, for the refinement). Between consecutive sign changes of p' the polynomial is
/// monotone, so each sign change of p is bracketed and bisected to the last bit.
fn poly_roots(c: &[f64], lo: f64, hi: f64, eval: &dyn Fn(f64) -> f64) -> Vec<f64> {
    let mut c = c.to_vec();
    while c.len() > 1 && c[c.len() - 1] == 0.0 {
        c.pop();
    }
    let deg = c.len() - 1;
    let mut knots = vec![lo];
    match deg {
        0 => return vec![],
        1 => {}
        2 => {
            let t = -c[1] / (2.0 * c[2]);
            if t > lo && t < hi {
                knots.push(t);
            }
        }
        _ => {
            let d: Vec<f64> = (1..=deg).map(|k| k as f64 * c[k]).collect();
            knots.extend(poly_roots(&d, lo, hi, &|t| horner(&d, t)));
        }
    }
    knots.push(hi);
    let mut out = Vec::new();
    for w in knots.windows(2) {
        let (mut a, mut b) = (w[0], w[1]);
        let (mut fa, fb) = (eval(a), eval(b));
        if fb == 0.0 {
            out.push(b);
            continue;
        }
        if fa == 0.0 || (fa < 0.0) == (fb < 0.0) {
            continue;
        }
        for _ in 0..2100 {
            let m = 0.5 * (a + b);
            if m <= a || m >= b {
                break;
            }
            let fm = eval(m);
            if fm == 0.0 {
                b = m;
                break;
            }
            if (fm < 0.0) == (fa < 0.0) {
                a = m;
                fa = fm;
            } else {
                b = m;
            }
        }
        out.push(b);
    }
    out.dedup();
    out
}

/// A tournament (winner) tree over a fixed set of keys: one pending event time per disk.
///
/// Each node holds the smallest (key, index) below it: the key's bits mapped to an unsigned
/// 64-bit integer of the same order ([`ordered`]) and the index. Ties go to the lower index,
/// which is the left subtree's winner (leaf `size + i` holds index `i`, so every index of a
/// left subtree is below every index of its right sibling): climbing from node `k`, the
/// sibling `k ^ 1` wins if its key is smaller, or equal while it is the left one, that is if
/// key(sibling) + [k is a left child] <= key(climber), one integer comparison, and the winner
/// is taken by two conditional moves. The chain from one level to the next is that compare and
/// move (two cycles; a packed 96-bit key took a 128-bit subtraction and two masks, six), and
/// there is no branch on the keys (the comparisons of keys and indices, and even an integer
/// `min`, were compiled into a branch per level that went either way at random, mispredicted
/// half the time: on x86-64 the moves are written out, elsewhere left to the compiler).
/// `update(i, t)` is O(log N) and always climbs to the root (most updates are of the top disk,
/// whose path has to be replayed to the root anyway; a check per level for an unchanged node
/// cost more than it saved); `top()` is O(1). Keys are times (s); −0 is stored as +0 (so that
/// the two compare equal, as `f64`s do); NaN keys are not expected.
#[derive(Debug, Clone)]
pub struct Tournament {
    size: usize,
    node: Vec<Node>,
}

/// A node of the tournament: the winner's ordered key and index.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Node {
    key: u64,
    index: u64,
}

/// The key `t` as an unsigned integer of the same order (IEEE 754 total order, −0 as +0).
#[inline]
fn ordered(t: f64) -> u64 {
    let b = (t + 0.0).to_bits();
    if b >> 63 == 1 {
        !b
    } else {
        b | 1 << 63
    }
}

/// The inverse of [`ordered`].
#[inline]
fn unordered(k: u64) -> f64 {
    f64::from_bits(if k >> 63 == 1 { k & !(1 << 63) } else { !k })
}

/// The winner of `w` (climbing from node `k`) and `s` (its sibling, node `k ^ 1`): the sibling
/// if its key is smaller, or equal while it is the left one (its indices are the lower).
#[inline(always)]
fn winner(w: Node, s: Node, k: usize) -> Node {
    // (+1 cannot wrap: no ordered key is u64::MAX, which would be a NaN)
    let biased = s.key.wrapping_add((!k & 1) as u64);
    #[cfg(target_arch = "x86_64")]
    {
        let (mut key, mut index) = (w.key, w.index);
        // SAFETY: a comparison and two conditional moves between registers; no memory, no
        // stack; the flags it sets are declared clobbered (asm!'s default).
        unsafe {
            std::arch::asm!(
                "cmp {b}, {key}",
                "cmovbe {key}, {sk}",
                "cmovbe {index}, {si}",
                b = in(reg) biased,
                sk = in(reg) s.key,
                si = in(reg) s.index,
                key = inout(reg) key,
                index = inout(reg) index,
                options(pure, nomem, nostack),
            );
        }
        Node { key, index }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        if biased <= w.key {
            s
        } else {
            w
        }
    }
}

impl Tournament {
    /// A tree of `n` keys, all +∞.
    pub fn new(n: usize) -> Tournament {
        let size = n.max(1).next_power_of_two();
        let inf = ordered(f64::INFINITY);
        let mut node = vec![Node { key: inf, index: 0 }; 2 * size];
        for i in 0..size {
            node[size + i].index = i as u64;
        }
        for k in (1..size).rev() {
            node[k] = winner(node[2 * k], node[2 * k + 1], 2 * k);
        }
        Tournament { size, node }
    }

    /// The index with the smallest key, and that key (s).
    #[inline]
    pub fn top(&self) -> (usize, f64) {
        let w = self.node[1];
        (w.index as usize, unordered(w.key))
    }

    /// The key of `i` (s).
    #[inline]
    pub fn key(&self, i: usize) -> f64 {
        unordered(self.node[self.size + i].key)
    }

    /// Sets the key of `i` to `t` (s) and replays its path towards the root.
    ///
    /// The candidate winner climbs in registers and meets, at each level, the sibling of the
    /// node it comes from: one load per level, from an address known in advance and never
    /// just stored, so the loads of the path overlap and the only chain is compare-and-select.
    #[inline]
    pub fn update(&mut self, i: usize, t: f64) {
        assert!(i < self.size, "tournament index {i} out of range");
        let node = self.node.as_mut_ptr();
        let mut k = self.size + i;
        let mut w = Node {
            key: ordered(t),
            index: i as u64,
        };
        // SAFETY: k < 2 size = node.len() on entry (checked above); each step halves k, and
        // k ^ 1 < 2 size and k >> 1 < size are in range for every k in [2, 2 size).
        unsafe {
            *node.add(k) = w;
            while k > 1 {
                w = winner(w, *node.add(k ^ 1), k);
                k >>= 1;
                *node.add(k) = w;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The next number of a xorshift64 generator (Marsaglia 2003) at `seed`.
    fn xorshift(seed: &mut u64) -> u64 {
        *seed ^= *seed << 13;
        *seed ^= *seed >> 7;
        *seed ^= *seed << 17;
        *seed
    }

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
    fn the_bounded_pair_test_agrees_with_the_full_one_bit_for_bit() {
        // over random pairs (approaching, receding, touching, overlapping by roundoff, grazing)
        // and bounds (0, small, large, ∞): a contact before the bound is the full test's, to the
        // bit, and no contact before it is ever reported
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut u = || (xorshift(&mut seed) >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
        let s2 = 4e-6;
        let mut hits = 0;
        for k in 0..200_000 {
            let (rx, ry) = match k % 4 {
                // touching, or overlapping / apart by roundoff
                0 => {
                    let a = std::f64::consts::PI * u();
                    let r = 0.002 * (1.0 + 1e-15 * u());
                    (r * a.cos(), r * a.sin())
                }
                _ => (0.004 * u(), 0.004 * u()),
            };
            let (vx, vy) = (u(), u());
            let before = [0.0, 1e-4 * u().abs(), 1e-2 * u().abs(), f64::INFINITY][k % 4];
            let full = pair_contact(rx, ry, vx, vy, s2);
            let bounded = pair_contact_before(rx, ry, vx, vy, s2, before);
            match full {
                Some(t) if t < before => {
                    assert_eq!(
                        bounded.map(f64::to_bits),
                        Some(t.to_bits()),
                        "{rx} {ry} {vx} {vy} {before}"
                    );
                    hits += 1;
                }
                _ => assert!(
                    bounded.is_none_or(|t| t >= before || Some(t) == full),
                    "{rx} {ry} {vx} {vy} {before}"
                ),
            }
        }
        assert!(hits > 10_000, "{hits}");
    }

    #[test]
    fn a_flying_disk_meets_a_riding_disk_at_the_root_of_the_quartic() {
        let s2 = 4e-6; // d = 2 mm
                       // disk j rides on a piston accelerating upward at 160 m/s², disk i falls onto it from
                       // 1 mm above contact, head on: relative acceleration −(160 + 9.8), closing at 0.3 m/s
        let (a, v, gap) = (-169.8, -0.3, 1e-3);
        let t = accel_pair_contact(0.0, 0.002 + gap, 0.0, v, a, s2, 1.0).unwrap();
        let exact = first_contact(gap, v, a).unwrap();
        assert!((t - exact).abs() < 1e-15, "{t:e} vs {exact:e}");
        // oblique: the distance at the root is σ, and it is the first such time
        let (rx, ry, vx, vy) = (0.0015, 0.0025, -0.05, -0.2);
        let t = accel_pair_contact(rx, ry, vx, vy, a, s2, 1.0).unwrap();
        let d2 = |t: f64| (rx + vx * t).powi(2) + (ry + vy * t + 0.5 * a * t * t).powi(2);
        assert!((d2(t) - s2).abs() < 1e-18, "{}", d2(t) - s2);
        for k in 0..1000 {
            assert!(d2(t * k as f64 / 1000.0) >= s2 - 1e-18);
        }
        // a brief graze that a coarse sampling would miss: the disks pass within σ for ~1 µs
        let t = accel_pair_contact(0.001999, 0.0, 0.0, 0.0, -1.0, s2, 1.0);
        assert!(
            t.is_none(),
            "receding along x? no: at rest, accelerating apart in y"
        );
        // touching and receding, but accelerated back: the later contact
        let t = accel_pair_contact(0.0, 0.002, 0.0, 0.1, -10.0, s2, 1.0).unwrap();
        assert!((t - 0.02).abs() < 1e-12, "{t}");
        // touching at rest and pressed together: now
        assert_eq!(
            accel_pair_contact(0.0, 0.002, 0.0, 0.0, -10.0, s2, 1.0),
            Some(0.0)
        );
        // beyond the horizon: none
        assert_eq!(accel_pair_contact(0.0, 0.002, 0.0, 0.1, -10.0, s2, 0.01), None);
    }

    #[test]
    fn a_touching_pair_pressed_together_with_a_roundoff_overlap_is_not_lost() {
        // gap −1e-17 m, receding at 1e-9 m/s, pressed at 170 m/s²: it never gets back above 0
        // on its parabola, but it is touching: the contact comes back at 2v/|a|
        let t = first_contact(-1e-17, 1e-9, -170.0).unwrap();
        assert!((t - 2e-9 / 170.0).abs() < 1e-22, "{t:e}");
        assert_eq!(first_contact(-1e-17, 0.0, -170.0), Some(0.0));
    }

    #[test]
    fn tournament_top_is_the_argmin_after_any_sequence_of_updates() {
        // against a linear scan, over updates that raise and lower keys, with many ties (keys
        // drawn from a few values) and sizes that are and are not powers of two
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || xorshift(&mut seed);
        for n in [1usize, 2, 3, 7, 8, 300, 513] {
            let mut t = Tournament::new(n);
            let mut keys = vec![f64::INFINITY; n];
            for _ in 0..20 * n {
                let i = (next() % n as u64) as usize;
                let k = match next() % 5 {
                    0 => f64::INFINITY,
                    v => v as f64 * 0.25,
                };
                t.update(i, k);
                keys[i] = k;
                let best = (0..n).fold(0, |b, j| if keys[j] < keys[b] { j } else { b });
                assert_eq!(t.top(), (best, keys[best]), "n = {n}");
                assert_eq!(t.key(i), k);
            }
        }
    }

    #[test]
    fn tournament_keys_keep_the_order_of_f64_over_signs_zeros_and_infinities() {
        // the integer keys order as the f64 keys do, −0 equals +0 (ties to the lower
        // index), and every key reads back exactly
        let keys = [
            f64::INFINITY,
            -1e-300,
            0.0,
            -0.0,
            f64::MIN_POSITIVE,
            5e-324,
            1.5,
            -2.5,
            f64::NEG_INFINITY,
            1.5,
            f64::MAX,
        ];
        for a in keys {
            for b in keys {
                assert_eq!(ordered(a) < ordered(b), a < b, "{a:e} < {b:e}");
                // a (index 0, the left node 2) against b (index 1, the right node 3), climbing
                // from either side: the smaller key, ties to the left
                let na = Node {
                    key: ordered(a),
                    index: 0,
                };
                let nb = Node {
                    key: ordered(b),
                    index: 1,
                };
                let expect = if b < a { nb } else { na };
                assert_eq!(winner(na, nb, 2), expect, "{a:e} from the left");
                assert_eq!(winner(nb, na, 3), expect, "{b:e} from the right");
            }
            assert_eq!(unordered(ordered(a)), a);
        }
        let mut t = Tournament::new(keys.len());
        for (i, &k) in keys.iter().enumerate() {
            t.update(i, k);
        }
        assert_eq!(t.top(), (8, f64::NEG_INFINITY));
        t.update(8, 7.0);
        assert_eq!(t.top(), (7, -2.5));
        t.update(7, 7.0);
        assert_eq!(t.top(), (1, -1e-300));
        t.update(1, 7.0);
        // 0 and −0 tie: the lower index wins, and −0 reads back as +0
        assert_eq!(t.top(), (2, 0.0));
        t.update(2, 7.0);
        let (i, k) = t.top();
        assert_eq!((i, k.to_bits()), (3, 0f64.to_bits()));
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
