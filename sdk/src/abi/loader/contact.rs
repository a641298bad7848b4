//! Contact-law handles: a plugin's (0.1, 0.2 or 0.3) and a law compiled into the host.

use super::*;
use crate::abi::kinds::normal_non_finite;
use crate::context::NormalContext;

/// A 0.1 contact law and the pairs it has been bound to (one per distinct effective mass and
/// radius: sdk 0.1 had no per-contact geometry).
pub(super) struct V1Law {
    ffi: Owned<v1::FfiContactLaw>,
    bound: Mutex<Vec<V1Entry>>,
}

/// (mass, radius, young) bits and the 0.1 law bound to that pair.
type V1Entry = (u64, u64, u64, Arc<V1Bound>);

struct V1Bound {
    ffi: Owned<v1::FfiBoundContact>,
}

impl V1Law {
    /// A 0.1 law, bound to no pair yet.
    pub(super) fn new(ffi: Owned<v1::FfiContactLaw>) -> V1Law {
        V1Law {
            ffi,
            bound: Mutex::new(Vec::new()),
        }
    }

    /// The law bound to the pair (mass, radius, young), binding it the first time.
    fn bound(&self, mass: f64, radius: f64, young: f64) -> Result<Arc<V1Bound>, LawError> {
        let key = (mass.to_bits(), radius.to_bits(), young.to_bits());
        let mut cache = self.bound.lock().unwrap_or_else(|p| p.into_inner());
        if let Some((.., b)) = cache.iter().find(|(m, r, e, _)| (*m, *r, *e) == key) {
            return Ok(b.clone());
        }
        let pair = Pair::new(mass, radius, young)?;
        let ffi = Owned::take(unsafe { (self.ffi.vtable.bind)(self.ffi.obj, &pair) })?;
        let b = Arc::new(V1Bound { ffi });
        cache.push((key.0, key.1, key.2, b.clone()));
        Ok(b)
    }
}

pub(super) enum ContactInner {
    V1(Arc<V1Law>),
    V2(Owned<v2::FfiContactLaw>),
    /// A 0.3 law, through the generic shape of its kind.
    V3(LawHandle<Normal>),
}

/// A configured contact law from a plugin.
pub struct ContactLawHandle {
    pub(super) inner: ContactInner,
    pub(super) info: LawInfo,
    pub(super) series: SdkSeries,
}

impl ContactLawHandle {
    /// The law's description.
    pub fn info(&self) -> &LawInfo {
        &self.info
    }

    /// The sdk series of the plugin it came from.
    pub fn series(&self) -> SdkSeries {
        self.series
    }

    /// Binds the law to a pair of materials (validated first).
    pub fn bind(&self, materials: &MaterialPair) -> Result<ContactModelHandle, LawError> {
        materials.validate()?;
        let inner = match &self.inner {
            ContactInner::V2(ffi) => {
                ModelInner::V2(Owned::take(unsafe { (ffi.vtable.bind)(ffi.obj, materials) })?)
            }
            ContactInner::V1(law) => ModelInner::V1 {
                law: law.clone(),
                young: materials.young,
            },
            ContactInner::V3(law) => ModelInner::V3(law.bind(materials)?),
        };
        Ok(ContactModelHandle::new(inner, &self.info))
    }
}

model_handle!(
    /// A contact law bound to a pair of materials: the hot path, per-contact geometry and
    /// history, every input and output checked.
    ContactModelHandle: Normal, call, v2: v2::FfiContactModel,
    /// A 0.1 law, bound on demand to each run of contacts of one geometry, of the materials'
    /// modulus `young`.
    V1 { law: Arc<V1Law>, young: f64 }
);

impl ContactModelHandle {
    fn panic_error(&self, msg: RString) -> LawError {
        LawError::new(
            ErrorKind::Panic,
            format!("contact law '{}' panicked: {}", self.name, msg),
        )
    }

    /// Evaluates every contact of `b` (see [`NormalBatch`]): forces into `b.force`, history
    /// updated in place. A non-finite input (or a mass or radius not > 0) is an error naming the
    /// contact, before anything of its block is computed; so is a non-finite output.
    pub fn force_batch(&self, b: NormalBatch<'_>) -> Result<(), LawError> {
        self.force_batch_with(b, None, EnergyOut::none()).map(|_| ())
    }

    /// As [`ContactModelHandle::force_batch`], with each contact's reach (m, ≥ 0: the contact
    /// ends at δ < −reach) written to `reach` and the energy outputs `energy` asks for:
    /// `Ok(true)` when those were written. A law of a plugin older than sdk 0.3 has reach 0 and
    /// reports energy as not available (`Ok(false)`).
    #[inline]
    pub fn force_batch_with(
        &self,
        b: NormalBatch<'_>,
        reach: Option<&mut [f64]>,
        energy: EnergyOut<'_>,
    ) -> Result<bool, LawError> {
        let context = None;
        self.call(
            NormalCall {
                batch: b,
                reach,
                context,
            },
            energy,
        )
    }

    /// As [`ContactModelHandle::force_batch_with`], with each contact's normal context (sdk
    /// 0.4: what the contact's other laws read) written to `context`, one per contact. A law of
    /// a plugin older than sdk 0.4 gives the defaults ([`NormalContext::default_for`]).
    #[inline]
    pub fn force_batch_context(
        &self,
        b: NormalBatch<'_>,
        reach: Option<&mut [f64]>,
        context: &mut [NormalContext],
        energy: EnergyOut<'_>,
    ) -> Result<bool, LawError> {
        let context = Some(context);
        self.call(
            NormalCall {
                batch: b,
                reach,
                context,
            },
            energy,
        )
    }

    /// A call of the normal kind (its batch, reach and contexts), through the ABI of the law's
    /// series; what a law of an older series leaves unwritten gets this sdk's defaults.
    #[inline]
    fn call(&self, call: NormalCall<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        match &self.inner {
            ModelInner::V3(m) => m.batch(call, energy),
            _ => self.call_older(call, energy),
        }
    }

    /// [`ContactModelHandle::call`] of a law of any series (out of line: the hot path is a law
    /// of sdk 0.3 or later).
    #[inline(never)]
    fn call_older(&self, mut call: NormalCall<'_>, energy: EnergyOut<'_>) -> Result<bool, LawError> {
        match &self.inner {
            ModelInner::V3(m) => m.batch(call, energy),
            ModelInner::V2(m) => {
                run_v2::<Normal>(
                    &self.name,
                    self.slots,
                    &mut call,
                    energy,
                    m.vtable.take_panic,
                    |ffi, fault| unsafe { (m.vtable.force_batch)(m.obj, &ffi.base.base, fault) },
                )?;
                Normal::older_defaults(&mut call);
                no_reach(call.reach)
            }
            ModelInner::V1 { law, young } => {
                Normal::check_lengths(&self.name, self.slots, &call)?;
                if !energy.lengths_ok(call.batch.force.len()) {
                    return Err(length_error(
                        "force_batch",
                        "the energy outputs must have one value per contact".into(),
                    ));
                }
                self.force_batch_v1(law, *young, &mut call.batch)?;
                Normal::older_defaults(&mut call);
                no_reach(call.reach)
            }
        }
    }

    /// A 0.1 law: inputs checked here (0.1 plugins do not), then one 0.1 batch call per run of
    /// contacts with the same geometry.
    fn force_batch_v1(&self, law: &V1Law, young: f64, b: &mut NormalBatch<'_>) -> Result<(), LawError> {
        let n = b.force.len();
        for i in 0..n {
            let checks = [
                (b.delta[i].is_finite(), BatchFault::DELTA, b.delta[i]),
                (b.rate[i].is_finite(), BatchFault::RATE, b.rate[i]),
                (
                    b.mass[i] > 0.0 && b.mass[i].is_finite(),
                    BatchFault::MASS,
                    b.mass[i],
                ),
                (
                    b.radius[i] > 0.0 && b.radius[i].is_finite(),
                    BatchFault::RADIUS,
                    b.radius[i],
                ),
            ];
            if let Some((_, f, v)) = checks.into_iter().find(|c| !c.0) {
                return Err(bad_input("contact", &self.name, f, i, v));
            }
        }
        let mut lo = 0;
        while lo < n {
            let (m, r) = (b.mass[lo], b.radius[lo]);
            let mut hi = lo + 1;
            while hi < n && b.mass[hi] == m && b.radius[hi] == r {
                hi += 1;
            }
            let bound = law.bound(m, r, young)?;
            let mut bad = 0usize;
            let st = unsafe {
                (bound.ffi.vtable.force_batch)(
                    bound.ffi.obj,
                    b.delta[lo..hi].as_ptr(),
                    b.rate[lo..hi].as_ptr(),
                    b.force[lo..hi].as_mut_ptr(),
                    hi - lo,
                    &mut bad,
                )
            };
            match st {
                v1::CallStatus::Ok => {}
                v1::CallStatus::Panic => return Err(self.panic_error((bound.ffi.vtable.take_panic)())),
                v1::CallStatus::NonFinite => {
                    let i = lo + bad.min(hi - lo - 1);
                    let c = Contact {
                        delta: b.delta[i],
                        rate: b.rate[i],
                        mass: m,
                        radius: r,
                    };
                    return Err(normal_non_finite(&self.name, b.force[i], c));
                }
            }
            lo = hi;
        }
        Ok(())
    }

    /// For benchmarks only: a 0.1 plugin's own bound-pair batch, called exactly as a 0.1 host
    /// called it (bound once to the pair of effective `mass` and `radius`, no input checks of
    /// the host), so that the 0.2 per-contact batch can be compared with it. `None` for a 0.2
    /// law.
    #[doc(hidden)]
    pub fn v1_bound_pair_batch(
        &self,
        mass: f64,
        radius: f64,
        d: &[f64],
        r: &[f64],
        o: &mut [f64],
    ) -> Option<Result<(), LawError>> {
        let ModelInner::V1 { law, young } = &self.inner else {
            return None;
        };
        let b = match law.bound(mass, radius, *young) {
            Ok(b) => b,
            Err(e) => return Some(Err(e)),
        };
        if d.len() != o.len() || r.len() != o.len() {
            return Some(Err(length_error(
                "force_batch",
                format!("{} {} {}", d.len(), r.len(), o.len()),
            )));
        }
        let mut bad = 0usize;
        Some(
            match unsafe {
                (b.ffi.vtable.force_batch)(
                    b.ffi.obj,
                    d.as_ptr(),
                    r.as_ptr(),
                    o.as_mut_ptr(),
                    o.len(),
                    &mut bad,
                )
            } {
                v1::CallStatus::Ok => Ok(()),
                _ => Err(LawError::new(ErrorKind::Other, "the 0.1 batch failed")),
            },
        )
    }

    /// The normal force (N) on one contact, history updated in place.
    pub fn force(&self, c: Contact, history: &mut [f64]) -> Result<f64, LawError> {
        c.force_through(history, |b| self.force_batch(b))
    }

    /// The law's derived constants for a contact of effective `mass` (kg) and `radius` (m).
    pub fn coefficients(&self, mass: f64, radius: f64) -> Result<Vec<Coefficient>, LawError> {
        match &self.inner {
            ModelInner::V2(m) => coefficients(unsafe { (m.vtable.coefficients)(m.obj, mass, radius) }),
            ModelInner::V3(m) => m.coefficients(mass, radius),
            ModelInner::V1 { law, young } => {
                let b = law.bound(mass, radius, *young)?;
                coefficients(unsafe { (b.ffi.vtable.coefficients)(b.ffi.obj) })
            }
        }
    }
}

/// A law older than sdk 0.3 has reach 0 (the contact ends when the overlap does) and no energy
/// outputs.
fn no_reach(reach: Option<&mut [f64]>) -> Result<bool, LawError> {
    if let Some(r) = reach {
        r.fill(0.0);
    }
    Ok(false)
}
