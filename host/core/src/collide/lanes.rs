//! Many head-on collisions of one law and one pair at once: a restitution curve ε(v0) in one
//! call, as a fit to measured restitutions evaluates it for every trial parameter set.
//!
//! A collision calls its law a few hundred times, one call after the other, each with a handful
//! of states; through a plugin most of a call's cost is the crossing itself, and the law waits
//! for the integrator and the integrator for the law. So the collisions of a curve run in
//! lockstep, each on a stackful coroutine ([`corosensei`]) of its own, running the very code of
//! [`collide`]:
//! - an extrapolation step (most of a collision's force evaluations) is handed over whole: the
//!   steps of all collisions waiting for one are taken together, every substep's states of all
//!   in one call of the law (`Lockstep`), with the arithmetic of [`super::extrap::step`] and
//!   [`Formulation`](super::two_body::Formulation);
//! - any other force call (the overlap scale, the first state of a phase, an event) hands its
//!   states over, and the states of all collisions waiting for forces go to the law in one call.
//!
//! The law evaluates each state on its own (a batch is elementwise), so each result is bit for
//! bit the one [`collide`] returns for that impact speed alone, errors included: a collision
//! whose states make a batch fail gets the law's answer to its own states.
//!
//! A law with per-contact history holds one collision's history at a time: its collisions run
//! one after the other, as does a recorded trajectory.

use super::extrap::Gbs;
use super::rk::{RhsError, Step};
use super::two_body::{collide, CollideError, Collision, ContactForce, Options, StepAsk};
use corosensei::stack::DefaultStack;
use corosensei::{CoroutineResult, ScopedCoroutine, ScopedCoroutineRef, Yielder};
use dashpot_sdk::{EndCriterion, LawError};
use std::cell::{Cell, RefCell};

/// The most collisions in lockstep: enough that one batch call carries ~40 states, few enough
/// that their stacks stay in cache.
pub const MAX_LANES: usize = 16;

/// Each coroutine's stack (bytes of address space; only the pages touched are used). The
/// integrator needs a few kilobytes; the rest is headroom for a plugin's own calls (history
/// commits, reach) made from the coroutine.
const STACK_BYTES: usize = 1 << 20;

/// The states of one round: each suspended collision appends its states to the buffer of the
/// next round and reads its forces from that of the current one (two buffers, so that resuming
/// a collision, which appends its next states, never disturbs the forces others still read).
#[derive(Default)]
struct Round {
    delta: Vec<f64>,
    rate: Vec<f64>,
    force: Vec<f64>,
}

/// What a suspended collision waits for.
enum Ask {
    /// Forces at the states `start .. start + count` of its round's buffers.
    Forces(usize, usize),
    /// An extrapolation step.
    Step(StepAsk),
}

/// The answer to an [`Ask`].
enum Reply {
    /// The forces are in the round's buffer (or the law failed on these states).
    Forces(Option<LawError>),
    /// The step and the force evaluations it made.
    Step(Result<Step<2>, RhsError>, usize),
}

type Lane<'a, 's> = ScopedCoroutine<'a, Reply, Ask, (), &'s mut DefaultStack>;
type LaneRef<'r, 's> = ScopedCoroutineRef<'r, Reply, Ask, (), &'s mut DefaultStack>;

/// The law as a collision in lockstep sees it: a force call suspends the collision until the
/// states of all collisions have been evaluated together.
struct LaneLaw<'a, C> {
    law: &'a C,
    yielder: &'a Yielder<Reply, Ask>,
    rounds: &'a [RefCell<Round>; 2],
    next: &'a Cell<usize>,
}

impl<C: ContactForce> ContactForce for LaneLaw<'_, C> {
    fn force(&self, delta: f64, rate: f64) -> Result<f64, LawError> {
        let mut out = [0.0];
        self.force_batch(&[delta], &[rate], &mut out)?;
        Ok(out[0])
    }

    fn force_batch(&self, delta: &[f64], rate: &[f64], out: &mut [f64]) -> Result<(), LawError> {
        let n = delta.len();
        if rate.len() != n || out.len() != n {
            return self.law.force_batch(delta, rate, out);
        }
        let which = self.next.get();
        let at = {
            let mut r = self.rounds[which].borrow_mut();
            let at = r.delta.len();
            // element by element: a call of memcpy costs more than these few states
            for i in 0..n {
                r.delta.push(delta[i]);
                r.rate.push(rate[i]);
            }
            at
        };
        match self.yielder.suspend(Ask::Forces(at, n)) {
            Reply::Forces(Some(e)) => Err(e),
            Reply::Step(..) => unreachable!("a force request is answered with forces"),
            Reply::Forces(None) => {
                let r = self.rounds[which].borrow();
                for (o, &f) in out.iter_mut().zip(&r.force[at..at + n]) {
                    *o = f;
                }
                Ok(())
            }
        }
    }

    fn has_history(&self) -> bool {
        self.law.has_history()
    }

    fn commit(&self, delta: f64, rate: f64) -> Result<(), LawError> {
        self.law.commit(delta, rate)
    }

    fn reset(&self) {
        self.law.reset()
    }

    fn reach(&self, delta: f64, rate: f64) -> Result<f64, LawError> {
        self.law.reach(delta, rate)
    }

    fn lockstep_step(&self, ask: &StepAsk) -> Option<(Result<Step<2>, RhsError>, usize)> {
        match self.yielder.suspend(Ask::Step(*ask)) {
            Reply::Step(s, evals) => Some((s, evals)),
            Reply::Forces(_) => unreachable!("a step request is answered with a step"),
        }
    }
}

thread_local! {
    /// Coroutine stacks kept for the next call on this thread (mapping one costs microseconds).
    static STACKS: RefCell<Vec<DefaultStack>> = const { RefCell::new(Vec::new()) };
}

/// The head-on collisions of effective `mass` (kg) under `law` at each impact speed of `v0s`
/// (m/s): element i is what [`collide`]`(law, mass, v0s[i], end, opt)` returns, bit for bit.
/// A law without history runs up to [`MAX_LANES`] collisions in lockstep, its states evaluated
/// in one batch call per round; a law with history, or a recorded trajectory, one collision
/// after the other.
pub fn collide_many<C: ContactForce>(
    law: &C,
    mass: f64,
    v0s: &[f64],
    end: EndCriterion,
    opt: &Options,
) -> Vec<Result<Collision, CollideError>> {
    let lanes = v0s.len().min(MAX_LANES);
    let one_by_one = || v0s.iter().map(|&v| collide(law, mass, v, end, opt)).collect();
    if lanes < 2 || law.has_history() || opt.record {
        return one_by_one();
    }
    let mut stacks = STACKS.with(|s| std::mem::take(&mut *s.borrow_mut()));
    while stacks.len() < lanes {
        match DefaultStack::new(STACK_BYTES) {
            Ok(s) => stacks.push(s),
            Err(_) => break,
        }
    }
    if stacks.len() < lanes {
        STACKS.with(|s| *s.borrow_mut() = stacks);
        return one_by_one();
    }
    let next = Cell::new(0usize);
    let (rounds, now) = (<[RefCell<Round>; 2]>::default(), Cell::new(0usize));
    let results: RefCell<Vec<Option<Result<Collision, CollideError>>>> =
        RefCell::new((0..v0s.len()).map(|_| None).collect());
    {
        let (next, results, rounds, now) = (&next, &results, &rounds, &now);
        let coroutines: Vec<Lane<'_, '_>> = stacks[..lanes]
            .iter_mut()
            .map(|stack| {
                ScopedCoroutine::with_stack(stack, move |yielder: &Yielder<Reply, Ask>, _| {
                    let lane = LaneLaw {
                        law,
                        yielder,
                        rounds,
                        next: now,
                    };
                    loop {
                        let i = next.get();
                        let Some(&v0) = v0s.get(i) else { break };
                        next.set(i + 1);
                        let c = collide(&lane, mass, v0, end, opt);
                        results.borrow_mut()[i] = Some(c);
                    }
                })
            })
            .collect();
        nest(coroutines, Vec::with_capacity(lanes), &mut |refs| {
            drive(law, refs, rounds, now)
        });
    }
    STACKS.with(|s| *s.borrow_mut() = stacks);
    results
        .into_inner()
        .into_iter()
        .zip(v0s)
        // every collision has run (the lanes take speeds until none is left): this is a guard
        .map(|(r, &v0)| r.unwrap_or_else(|| collide(law, mass, v0, end, opt)))
        .collect()
}

/// Opens the scope of each coroutine in turn (a scope keeps what the coroutine borrows alive
/// while it may run), then drives them all.
fn nest<'s>(
    mut coroutines: Vec<Lane<'_, 's>>,
    refs: Vec<LaneRef<'_, 's>>,
    drive: &mut dyn FnMut(&mut [LaneRef<'_, 's>]),
) {
    match coroutines.pop() {
        None => {
            let mut refs = refs;
            drive(&mut refs)
        }
        Some(c) => c.scope(|r| {
            let mut refs = refs;
            refs.push(r);
            nest(coroutines, refs, drive)
        }),
    }
}

/// Runs the collisions to their ends. Each round answers either every collision waiting for
/// forces (their states in one call of `law`) or every collision waiting for a step (their
/// steps in lockstep, each substep's states of all in one call).
fn drive<C: ContactForce>(
    law: &C,
    lanes: &mut [LaneRef<'_, '_>],
    rounds: &[RefCell<Round>; 2],
    next: &Cell<usize>,
) {
    let ask = |r: CoroutineResult<Ask, ()>| match r {
        CoroutineResult::Yield(a) => Some(a),
        CoroutineResult::Return(()) => None,
    };
    next.set(0);
    let mut pending: Vec<Option<Ask>> = lanes
        .iter_mut()
        .map(|l| ask(l.resume(Reply::Forces(None))))
        .collect();
    let mut steps = Lockstep::default();
    loop {
        if pending.iter().any(|a| matches!(a, Some(Ask::Forces(..)))) {
            let now = next.get();
            next.set(1 - now);
            {
                let mut r = rounds[1 - now].borrow_mut();
                r.delta.clear();
                r.rate.clear();
            }
            let together = {
                let mut r = rounds[now].borrow_mut();
                let Round { delta, rate, force } = &mut *r;
                batch(law, delta, rate, force)
            };
            for (lane, slot) in lanes.iter_mut().zip(pending.iter_mut()) {
                let Some(Ask::Forces(at, n)) = *slot else { continue };
                let err = match together {
                    true => None,
                    false => {
                        let mut r = rounds[now].borrow_mut();
                        let Round { delta, rate, force } = &mut *r;
                        alone(law, delta, rate, force, (at, n))
                    }
                };
                *slot = ask(lane.resume(Reply::Forces(err)));
            }
        } else if pending.iter().any(Option::is_some) {
            steps.run(law, &mut pending);
            for (lane, (slot, done)) in lanes
                .iter_mut()
                .zip(pending.iter_mut().zip(steps.done.iter_mut()))
            {
                if let Some((s, evals)) = done.take() {
                    *slot = ask(lane.resume(Reply::Step(s, evals)));
                }
            }
        } else {
            break;
        }
    }
}

/// The forces at all the states `delta` (m), `rate` (m/s) into `force` (N), in one call of
/// `law`; whether it succeeded.
fn batch<C: ContactForce>(law: &C, delta: &[f64], rate: &[f64], force: &mut Vec<f64>) -> bool {
    force.clear();
    force.resize(delta.len(), 0.0);
    law.force_batch(delta, rate, force).is_ok()
}

/// After a failed [`batch`]: the states `start .. start + count` of one collision alone, so that
/// it gets the law's answer to its own states, as it would alone (`None`: they succeed).
fn alone<C: ContactForce>(
    law: &C,
    delta: &[f64],
    rate: &[f64],
    force: &mut [f64],
    (at, n): (usize, usize),
) -> Option<LawError> {
    let span = at..at + n;
    law.force_batch(&delta[span.clone()], &rate[span.clone()], &mut force[span])
        .err()
}

/// The extrapolation steps of the collisions waiting for one, taken together: every substep's
/// states of all in one call of the law.
#[derive(Default)]
struct Lockstep {
    /// Per collision: the step in the making, its formulation, its evaluations, its failure
    /// (the first `count`; the rest are kept for their memory).
    taking: Vec<Taking>,
    count: usize,
    /// Per collision (index of the lane): the finished step and its evaluations.
    done: Vec<Option<(Result<Step<2>, RhsError>, usize)>>,
    delta: Vec<f64>,
    rate: Vec<f64>,
    force: Vec<f64>,
}

/// One collision's step in the making.
struct Taking {
    lane: usize,
    ask: StepAsk,
    gbs: Gbs<2>,
    evals: usize,
    failed: Option<RhsError>,
    /// Where its states of this substep are in the batch: (start, count).
    span: (usize, usize),
    /// The step's result and error estimate.
    end: ([f64; 2], [f64; 2]),
}

impl Lockstep {
    /// Takes the step each `Ask::Step` of `pending` asks for (leaving `None` there), the
    /// results in `done` by lane, with the arithmetic of [`super::extrap::step`] and of
    /// [`Formulation`](super::two_body::Formulation), so each is the step the collision would have taken alone.
    fn run<C: ContactForce>(&mut self, law: &C, pending: &mut [Option<Ask>]) {
        self.done.clear();
        self.done.resize_with(pending.len(), || None);
        self.count = 0;
        for (lane, slot) in pending.iter_mut().enumerate() {
            if let Some(Ask::Step(a)) = slot.take_if(|a| matches!(a, Ask::Step(_))) {
                if self.count == self.taking.len() {
                    self.taking.push(Taking {
                        lane,
                        gbs: Gbs::new(a.x, &a.y, &a.f0, a.h, a.k),
                        ask: a,
                        evals: 0,
                        failed: None,
                        span: (0, 0),
                        end: ([0.0; 2], [0.0; 2]),
                    });
                } else {
                    let t = &mut self.taking[self.count];
                    t.gbs.restart(a.x, &a.y, &a.f0, a.h, a.k);
                    (t.lane, t.ask, t.evals, t.failed) = (lane, a, 0, None);
                }
                self.count += 1;
            }
        }
        let n_steps = self.count;
        let rounds = self.taking[..n_steps]
            .iter()
            .map(|t| t.gbs.rounds())
            .max()
            .unwrap_or(0);
        for m in 1..rounds {
            self.delta.clear();
            self.rate.clear();
            for t in self.taking[..n_steps]
                .iter_mut()
                .filter(|t| t.failed.is_none() && m < t.gbs.rounds())
            {
                let (xs, zs) = t.gbs.points(m);
                let n = xs.len();
                let at = self.delta.len();
                let mut ok = Ok(());
                for i in 0..n {
                    match t.ask.form.state(xs[i], &zs[i]) {
                        Ok((d, v)) => {
                            self.delta.push(d);
                            self.rate.push(v);
                        }
                        Err(e) => {
                            ok = Err(e);
                            break;
                        }
                    }
                }
                if let Err(e) = ok {
                    self.delta.truncate(at);
                    self.rate.truncate(at);
                    t.failed = Some(e);
                    continue;
                }
                t.evals += n;
                t.span = (at, n);
            }
            self.evaluate(law, |t| t.failed.is_none() && m < t.gbs.rounds());
            for t in self.taking[..n_steps]
                .iter_mut()
                .filter(|t| t.failed.is_none() && m < t.gbs.rounds())
            {
                let (at, n) = t.span;
                let mut fs = [[0.0; 2]; Gbs::<2>::MAX_POINTS];
                for ((f, &x), i) in fs[..n].iter_mut().zip(t.gbs.abscissae(m)).zip(at..) {
                    *f = t.ask.form.rhs_of(x, self.rate[i], self.force[i]);
                }
                t.gbs.advance(m, &fs[..n]);
            }
        }
        // the right-hand side at the end of each step: the first of its next
        self.delta.clear();
        self.rate.clear();
        for t in self.taking[..n_steps].iter_mut() {
            let (y1, err) = t.gbs.finish();
            t.end = (y1, err);
            if t.failed.is_some() {
                continue;
            }
            let x1 = t.ask.x + t.ask.h;
            match t.ask.form.state(x1, &y1) {
                Ok((d, v)) => {
                    t.span = (self.delta.len(), 1);
                    self.delta.push(d);
                    self.rate.push(v);
                    t.evals += 1;
                }
                Err(e) => t.failed = Some(e),
            }
        }
        self.evaluate(law, |t| t.failed.is_none());
        for t in self.taking[..n_steps].iter_mut() {
            let (y1, err) = t.end;
            let r = match t.failed.take() {
                Some(e) => Err(e),
                None => {
                    let i = t.span.0;
                    let f1 = t
                        .ask
                        .form
                        .rhs_of_one(t.ask.x + t.ask.h, self.rate[i], self.force[i]);
                    Ok(Step { y: y1, f: f1, err })
                }
            };
            self.done[t.lane] = Some((r, t.evals));
        }
    }

    /// The forces at the batch's states of the steps `active` selects, in one call of `law`;
    /// if it fails, each step's states alone, and a step whose states fail fails with the
    /// law's error, as it would alone.
    fn evaluate<C: ContactForce>(&mut self, law: &C, active: impl Fn(&Taking) -> bool) {
        if batch(law, &self.delta, &self.rate, &mut self.force) {
            return;
        }
        for t in self.taking[..self.count].iter_mut().filter(|t| active(t)) {
            if let Some(e) = alone(law, &self.delta, &self.rate, &mut self.force, t.span) {
                t.failed = Some(RhsError::Law(e));
            }
        }
    }
}
