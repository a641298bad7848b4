//! The pool kept awake through a block of steps.
//!
//! A step of a large pile is a few parallel passes (one in an open box; the second half-kick
//! and the state check in a bounded one; a list build now and then) between serial stretches
//! (the partners' forces and the counts). Between two parallel passes, rayon's idle workers
//! spin a few dozen rounds, then sleep; waking one costs the step some 100–250 µs on a
//! virtual machine, where the sleeping thread's core has halted and must be scheduled again
//! by the hypervisor, out of a step of a few milliseconds. OpenMP runtimes keep their threads
//! spinning between the parallel regions of a run for this reason. Here, for a block of
//! steps, every other worker of the pool runs a job that looks for rayon work without pause
//! (`rayon::yield_now`, which steals), so that each pass's tasks are taken at once; the job
//! ends with the block. At the end of a pass, the calling thread waits for the others' last
//! tasks without sleeping either ([`map_claimed`]).
//!
//! Nothing in the steps depends on it: the tasks and their results are the same, only who
//! waits and how differs. The cost is the spinning workers' cores during the serial
//! stretches, which nothing else would use while the steps run; on a pool larger than the
//! machine, the waits yield the core between looks. One block at a time in the process keeps
//! its pool awake: a spinner runs whatever rayon work it finds, and two blocks' spinners, each
//! run by the other block's thread while it waits inside rayon, would wait for each other's
//! end. Another block running meanwhile runs as rayon runs it, with sleeping workers, and a
//! thread of it that picks up one of the awake block's spinners while it waits inside rayon
//! is held until that block ends: slower, never stuck (engines stepped side by side on one
//! pool are better given a pool each).

use crossbeam_utils::Backoff;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

/// Runs `f` on a rayon worker with every other worker of its pool looking for work without
/// sleeping until `f` returns (or unwinds). Called off a pool, `f` runs on a worker of the
/// global pool (the caller waits once for the block, not once per step); on a pool of one
/// thread, `f` just runs.
pub(super) fn with_pool_awake<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    if rayon::current_num_threads() < 2 {
        return f();
    }
    let Some(me) = rayon::current_thread_index() else {
        return rayon::scope(|_| with_pool_awake(f));
    };
    // one block at a time (see the module doc)
    static AWAKE: AtomicBool = AtomicBool::new(false);
    if AWAKE
        .compare_exchange(false, true, Ordering::Acquire, Ordering::Relaxed)
        .is_err()
    {
        return f();
    }
    // (dropped after the scope, which waits for the spinners)
    let _awake = OnDrop(|| AWAKE.store(false, Ordering::Release));
    let stop = AtomicBool::new(false);
    rayon::scope(|s| {
        for _ in 1..rayon::current_num_threads() {
            s.spawn(|_| {
                // a spinner picked up by the calling worker itself (while it waits for some
                // task of `f`) returns at once: it would spin until `f`, which it holds up,
                // returned
                if rayon::current_thread_index() == Some(me) {
                    return;
                }
                // spin, then yield the core between looks (a pool larger than the machine)
                let wait = Backoff::new();
                while !stop.load(Ordering::Acquire) {
                    if rayon::yield_now() == Some(rayon::Yield::Executed) {
                        wait.reset();
                    } else {
                        wait.snooze();
                    }
                }
            });
        }
        // `stop` however `f` ends, so that the scope's wait for the spinners ends
        let _stop = OnDrop(|| stop.store(true, Ordering::Release));
        f()
    })
}

/// Which is faster for a pile on this machine now, a block of steps in parallel or on the
/// calling thread alone. A second thread mostly pays, but not always: on a virtual machine
/// whose two cores do not share a cache at times, handing a range's particles from one core to
/// the other each step can cost more than the second core gains (BENCHMARKS.md, "Against
/// LAMMPS"). The engine steps in blocks the faster way, and now and then tries the other on a
/// short block, compared with the blocks of the current way just before and after it (a
/// pile's cost per step changes as it falls and settles, so only neighbouring blocks compare):
/// a change of the machine's state is seen within a few thousand steps.
#[derive(Debug, Clone)]
pub(super) struct Pace {
    /// The current way: in parallel, or not.
    parallel: bool,
    /// Wall time per step (ns) of the current way's last block (0: none yet).
    last: f64,
    /// Wall time per step of the other way's trial, waiting for the next block to compare with.
    trial: Option<f64>,
    /// The other way's time over the current way's at the last trial.
    margin: f64,
    /// Blocks timed so far.
    blocks: u64,
}

impl Default for Pace {
    fn default() -> Self {
        Pace {
            parallel: true,
            last: 0.0,
            trial: None,
            margin: 1.0,
            blocks: 0,
        }
    }
}

/// Steps of a block, and of a block that tries the other way.
const PACE_BLOCK: u64 = 250;
const PACE_TRIAL: u64 = 50;

impl Pace {
    /// Whether to run the next block in parallel, and how many of the `left` steps it takes.
    pub(super) fn next(&self, left: u64) -> (bool, u64) {
        // a trial after the first block, then often while the two ways are close, rarely once
        // the other is far behind
        let every = if self.margin > 1.3 { 64 } else { 16 };
        let trial = self.last > 0.0 && self.trial.is_none() && (self.blocks == 1 || self.blocks % every == 0);
        if trial {
            (!self.parallel, PACE_TRIAL.min(left))
        } else {
            (self.parallel, PACE_BLOCK.min(left))
        }
    }

    /// Records a block of `steps` run in parallel or not that took `took`.
    pub(super) fn record(&mut self, parallel: bool, took: std::time::Duration, steps: u64) {
        // a few steps time too little to tell
        if steps < PACE_TRIAL {
            return;
        }
        let ns = took.as_nanos() as f64 / steps as f64;
        self.blocks += 1;
        if parallel != self.parallel {
            self.trial = Some(ns);
            return;
        }
        if let Some(other) = self.trial.take() {
            let current = 0.5 * (self.last + ns);
            self.margin = other / current;
            // the other way is taken when it is clearly faster
            if self.margin < 0.95 {
                self.parallel = !self.parallel;
                self.margin = 1.0 / self.margin;
                self.last = other;
                return;
            }
        }
        self.last = ns;
    }
}

/// Runs its closure when dropped: at the end of the scope it guards, however that ends (a
/// panic included), so that no thread is left waiting for a flag.
pub(super) struct OnDrop<F: FnMut()>(pub F);

impl<F: FnMut()> Drop for OnDrop<F> {
    fn drop(&mut self) {
        (self.0)()
    }
}

/// Waits until `done()`: spinning, then yielding the core between looks (for a pool larger
/// than the machine).
pub(super) fn spin_until(done: impl Fn() -> bool) {
    let wait = Backoff::new();
    while !done() {
        wait.snooze();
    }
}

fn lock<X>(m: &Mutex<X>) -> MutexGuard<'_, X> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

/// The items of a parallel map, each with its result behind a lock, and how many are done.
struct Slots<I, T> {
    slots: Vec<Mutex<(Option<I>, Option<T>)>>,
    done: AtomicUsize,
}

impl<I: Send, T: Send> Slots<I, T> {
    fn new(items: Vec<I>) -> Self {
        let slots = items.into_iter().map(|i| Mutex::new((Some(i), None))).collect();
        Slots {
            slots,
            done: AtomicUsize::new(0),
        }
    }

    /// Runs item `k` through `work` and keeps its result (an item already taken is left).
    fn run(&self, k: usize, work: &impl Fn(I) -> T) {
        // counted done however the work ends, so that the caller's wait ends
        let _done = OnDrop(|| {
            self.done.fetch_add(1, Ordering::Release);
        });
        let item = lock(&self.slots[k]).0.take();
        if let Some(item) = item {
            let out = work(item);
            lock(&self.slots[k]).1 = Some(out);
        }
    }

    /// `claim` on `threads` threads of the pool, the calling one among them, which then waits
    /// without sleeping until every item is done; the results in the items' order.
    fn run_all(self, threads: usize, claim: impl Fn(&Self) + Sync) -> Vec<T> {
        let n = self.slots.len();
        rayon::scope(|s| {
            for _ in 1..threads {
                s.spawn(|_| claim(&self));
            }
            claim(&self);
            spin_until(|| self.done.load(Ordering::Acquire) >= n);
        });
        // every item's work returned (a panic would have left the scope above)
        self.slots
            .into_iter()
            .filter_map(|m| m.into_inner().unwrap_or_else(PoisonError::into_inner).1)
            .collect()
    }
}

/// `work` applied to each of `items` on the threads of the pool, the results in the items'
/// order. Each item is taken, in order, by whichever thread is free (the calling one among
/// them), so that a thread held up leaves the later items to the others; the calling thread
/// then waits for the last ones without sleeping (a sleeping caller would be woken by the
/// last task's thread at the cost rayon's own wait pays on a virtual machine: see the module
/// doc). A panic in `work` reaches the caller once every item has been taken.
pub(super) fn map_claimed<I: Send, T: Send>(items: Vec<I>, work: impl Fn(I) -> T + Sync) -> Vec<T> {
    let n = items.len();
    let threads = rayon::current_num_threads().min(n);
    if threads < 2 {
        return items.into_iter().map(work).collect();
    }
    let next = AtomicUsize::new(0);
    Slots::new(items).run_all(threads, |s| loop {
        let k = next.fetch_add(1, Ordering::Relaxed);
        if k >= n {
            return;
        }
        s.run(k, &work);
    })
}

/// `work` applied to each of `items` on the threads of the pool, the results in the items'
/// order, each item run by the same thread from call to call where it can: item 0 by the
/// calling thread, item r by the r-th worker after it (the workers' indices taken round the
/// pool), so that a thread works on the same data at every step and finds it in its cache.
/// A thread done with its own item takes any item not yet taken, in order (a thread held up,
/// or not woken, leaves its item to the others); the calling thread then waits for the last
/// ones without sleeping (as [`map_claimed`]). A panic in `work` reaches the caller once
/// every item has been taken.
pub(super) fn map_ranked<I: Send, T: Send>(items: Vec<I>, work: impl Fn(I) -> T + Sync) -> Vec<T> {
    let n = items.len();
    let threads = rayon::current_num_threads().min(n);
    let Some(me) = rayon::current_thread_index().filter(|_| threads >= 2) else {
        return map_claimed(items, work);
    };
    let pool = rayon::current_num_threads();
    let taken: Vec<AtomicBool> = (0..n).map(|_| AtomicBool::new(false)).collect();
    let run = |s: &Slots<I, T>, k: usize| {
        if !taken[k].swap(true, Ordering::AcqRel) {
            s.run(k, &work);
        }
    };
    Slots::new(items).run_all(threads, |s| {
        let rank = rayon::current_thread_index().map_or(0, |w| (w + pool - me) % pool);
        if rank < n {
            run(s, rank);
        }
        (0..n).for_each(|k| run(s, k));
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a pool")
    }

    /// Pace takes the way that is faster now: parallel first, the other way tried after the
    /// first block and then now and then, a switch when the trial beats its neighbours by 5 %,
    /// and back when the machine changes again; every step is run exactly once.
    #[test]
    fn pace_follows_the_faster_way_as_the_machine_changes() {
        use std::time::Duration;
        // per-step cost (ns) of each way, as a function of the step reached
        let run = |cost: &dyn Fn(bool, u64) -> f64, total: u64| -> (Pace, Vec<(bool, u64)>) {
            let (mut pace, mut done, mut log) = (Pace::default(), 0, Vec::new());
            while done < total {
                let (way, steps) = pace.next(total - done);
                assert!(steps > 0 && steps <= total - done);
                let ns = cost(way, done) * steps as f64;
                pace.record(way, Duration::from_nanos(ns as u64), steps);
                log.push((way, steps));
                done += steps;
            }
            (pace, log)
        };
        // parallel twice as fast: it stays parallel, serial tried on short blocks only
        let (pace, log) = run(&|par, _| if par { 100.0 } else { 200.0 }, 100_000);
        assert!(pace.parallel);
        let serial: u64 = log.iter().filter(|b| !b.0).map(|b| b.1).sum();
        assert!(serial > 0 && serial <= 100_000 / 50, "{serial} serial steps");
        // parallel slower (the cores stopped sharing a cache): serial from the first trial on
        let (pace, log) = run(&|par, _| if par { 240.0 } else { 200.0 }, 100_000);
        assert!(!pace.parallel);
        assert!(log.iter().skip(3).filter(|b| b.0).map(|b| b.1).sum::<u64>() <= 100_000 / 50);
        // the machine changes back and forth: the last way is the one faster at the end
        let flip = |par: bool, at: u64| {
            let slow = (at / 40_000) % 2 == 1;
            match (par, slow) {
                (true, false) => 100.0,
                (true, true) => 260.0,
                (false, _) => 200.0,
            }
        };
        let (pace, _) = run(&flip, 100_000);
        assert!(pace.parallel, "steps 80,000-100,000 are fast in parallel");
        let (pace, _) = run(&flip, 70_000);
        assert!(!pace.parallel, "steps 40,000-70,000 are slow in parallel");
        // a cost rising fast as the pile settles is not mistaken for the other way's
        let (pace, _) = run(
            &|par, at| (1.0 + at as f64 / 2000.0) * if par { 100.0 } else { 160.0 },
            60_000,
        );
        assert!(pace.parallel);
    }

    #[test]
    fn every_item_is_worked_once_and_the_results_keep_the_items_order() {
        for threads in [1, 2, 3] {
            let calls = AtomicUsize::new(0);
            let out = pool(threads).install(|| {
                with_pool_awake(|| {
                    map_claimed((0..37u64).collect(), |i| {
                        calls.fetch_add(1, Ordering::Relaxed);
                        // uneven work, so that the threads take items out of turn
                        std::hint::black_box((0..(i % 5) * 1000).map(std::hint::black_box).sum::<u64>());
                        i * i
                    })
                })
            });
            assert_eq!(calls.load(Ordering::Relaxed), 37);
            assert_eq!(
                out,
                (0..37u64).map(|i| i * i).collect::<Vec<_>>(),
                "{threads} threads"
            );
        }
    }

    #[test]
    fn two_blocks_at_once_on_one_pool_both_end() {
        for threads in [2, 3, 4] {
            let (a, b) = pool(threads).install(|| {
                rayon::join(
                    || with_pool_awake(|| map_claimed((0..50u64).collect(), |i| i + 1)),
                    || with_pool_awake(|| map_claimed((0..50u64).collect(), |i| i + 2)),
                )
            });
            assert_eq!(a.iter().sum::<u64>(), 1275);
            assert_eq!(b.iter().sum::<u64>(), 1325);
        }
    }

    #[test]
    fn a_panicking_item_reaches_the_caller_and_nothing_hangs() {
        for threads in [2, 3] {
            let p = pool(threads);
            let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                p.install(|| {
                    with_pool_awake(|| {
                        map_claimed((0..8).collect(), |i: i32| {
                            assert!(i != 5, "item five");
                            i
                        })
                    })
                })
            }));
            let err = r.expect_err("the panic must reach the caller");
            let msg = err
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| err.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            assert!(msg.contains("item five"), "{msg}");
            // the pool still works
            assert_eq!(p.install(|| map_claimed(vec![1, 2, 3], |i| 2 * i)), vec![2, 4, 6]);
        }
    }
}
