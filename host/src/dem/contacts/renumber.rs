//! The contacts carried through a renumbering of the particles (the engine's memory order,
//! see [`crate::dem::integrator::Engine::user_index`]): each contact's key moved to the new
//! numbers, the sets rebuilt in the new chunks in key order, with their history.

use super::{ContactSet, Contacts};

impl Contacts {
    /// Renumbers the particles of the current contacts, kept in chunks of `chunk` particles:
    /// particle `k` becomes `new_of[k]`. Pair
    /// contacts (`pairs`) keep i < j (the history needs no change: the laws see a pair from the
    /// partner the user numbered first, whatever the engine's numbers); wall contacts keep
    /// their wall. Only what the next gathering reads of the previous sets is carried: keys,
    /// histories, the last-step flags, the reaches and the springs' elastic energy. The work is a counting sort by the new
    /// i, then each particle's few partners sorted: linear in the contacts.
    pub fn renumber(&mut self, new_of: &[u32], pairs: bool, chunk: usize) {
        let n = new_of.len();
        let nc = self.classes();
        let chunks = self.chunks.len() / nc;
        if chunks == 0 {
            return;
        }
        let new_key = |i: u32, j: u32| -> (u32, u32) {
            let a = new_of[i as usize];
            if !pairs {
                return (a, j);
            }
            let b = new_of[j as usize];
            (a.min(b), a.max(b))
        };
        // each contact's (new j, set, index in the set), bucketed by its new i
        let mut start = vec![0u32; n + 1];
        for set in &self.chunks {
            for m in 0..set.len() {
                start[new_key(set.i[m], set.j[m]).0 as usize + 1] += 1;
            }
        }
        for k in 0..n {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut recs = vec![(0u32, 0u32, 0u32); start[n] as usize];
        for (c, set) in self.chunks.iter().enumerate() {
            for m in 0..set.len() {
                let (a, b) = new_key(set.i[m], set.j[m]);
                recs[fill[a as usize] as usize] = (b, c as u32, m as u32);
                fill[a as usize] += 1;
            }
        }
        for k in 0..n {
            recs[start[k] as usize..start[k + 1] as usize].sort_unstable_by_key(|r| r.0);
        }
        let _ = self.buffers(chunks);
        // (a contact keeps its class: the set of its class in its new chunk)
        let (mut count, mut at) = (vec![0usize; nc], vec![0usize; nc]);
        for c in 0..chunks {
            let (a, b) = (c * chunk, ((c + 1) * chunk).min(n));
            let (lo, hi) = (start[a] as usize, start[b] as usize);
            count.iter_mut().for_each(|k| *k = 0);
            for &(_, sc, _) in &recs[lo..hi] {
                count[sc as usize % nc] += 1;
            }
            for (cl, &k) in count.iter().enumerate() {
                let dst = &mut self.spare[c * nc + cl];
                dst.first = a;
                dst.sign.clear();
                dst.size(k);
            }
            at.iter_mut().for_each(|k| *k = 0);
            for row in a..b {
                let (r0, r1) = (start[row] as usize, start[row + 1] as usize);
                for &(j, sc, m) in &recs[r0..r1] {
                    let cl = sc as usize % nc;
                    let src = &self.chunks[sc as usize];
                    move_history(
                        &mut self.spare[c * nc + cl],
                        at[cl],
                        row as u32,
                        j,
                        src,
                        m as usize,
                    );
                    at[cl] += 1;
                }
            }
        }
        self.swap();
    }
}

/// Contact `m` of `src` as contact `k` of `dst`, keyed (`i`, `j`): what the merge of the next
/// gathering reads (histories, last-step flag, reach, the springs' elastic energy).
fn move_history(dst: &mut ContactSet, k: usize, i: u32, j: u32, src: &ContactSet, m: usize) {
    dst.i[k] = i;
    dst.j[k] = j;
    dst.last[k] = src.last[m];
    if dst.reach_bound > 0.0 {
        dst.reach[k] = src.reach[m];
    }
    let copy = |d: &mut [f64], s: &[f64], slots: usize| {
        d[k * slots..(k + 1) * slots].copy_from_slice(&s[m * slots..(m + 1) * slots]);
    };
    copy(&mut dst.hist_n, &src.hist_n, dst.slots_n);
    copy(&mut dst.hist_t, &src.hist_t, dst.slots_t);
    if dst.rotational() {
        copy(&mut dst.hist_r, &src.hist_r, dst.slots_r.unwrap_or(0));
        copy(&mut dst.hist_w, &src.hist_w, dst.slots_w.unwrap_or(0));
    }
    if dst.energy {
        // the springs' energy, which the gathering books if the contact ends
        for (d, s) in dst.elastic.iter_mut().zip(&src.elastic).skip(1) {
            d[k] = s[m];
        }
    }
}
