//! Contact-law handles: a plugin's (0.1, 0.2 or 0.3) and a law compiled into the host.

use super::*;

/// A 0.1 contact law and the pairs it has been bound to (one per distinct effective mass and
/// radius: sdk 0.1 had no per-contact geometry).
pub(super) struct V1Law {
    ffi: v1::FfiContactLaw,
    bound: Mutex<Vec<V1Entry>>,
}

impl Drop for V1Law {
    fn drop(&mut self) {
        unsafe { (self.ffi.vtable.drop)(self.ffi.obj) }
    }
}

/// (mass, radius, young) bits and the 0.1 law bound to that pair.
type V1Entry = (u64, u64, u64, Arc<V1Bound>);

struct V1Bound {
    ffi: v1::FfiBoundContact,
}

impl Drop for V1Bound {
    fn drop(&mut self) {
        unsafe { (self.ffi.vtable.drop)(self.ffi.obj) }
    }
}

impl V1Law {
    /// A 0.1 law, bound to no pair yet.
    pub(super) fn new(ffi: v1::FfiContactLaw) -> V1Law {
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
        let b = match unsafe { (self.ffi.vtable.bind)(self.ffi.obj, &pair) } {
            RResult::ROk(ffi) => Arc::new(V1Bound { ffi }),
            RResult::RErr(e) => return Err(e.into()),
        };
        cache.push((key.0, key.1, key.2, b.clone()));
        Ok(b)
    }
}

pub(super) enum ContactInner {
    V1(Arc<V1Law>),
    V2(FfiContactLaw),
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
            ContactInner::V2(ffi) => match unsafe { (ffi.vtable.bind)(ffi.obj, materials) } {
                RResult::ROk(m) => ModelInner::V2(m),
                RResult::RErr(e) => return Err(e.into()),
            },
            ContactInner::V1(law) => ModelInner::V1 {
                law: law.clone(),
                young: materials.young,
            },
            ContactInner::V3(law) => ModelInner::V3(law.bind(materials)?),
        };
        Ok(ContactModelHandle {
            inner,
            name: self.info.name.to_string(),
            slots: self.info.history.len(),
        })
    }
}

impl Drop for ContactLawHandle {
    fn drop(&mut self) {
        if let ContactInner::V2(ffi) = &self.inner {
            unsafe { (ffi.vtable.drop)(ffi.obj) }
        }
    }
}

enum ModelInner {
    V1 { law: Arc<V1Law>, young: f64 },
    V2(FfiContactModel),
    V3(ModelHandle<Normal>),
}

/// Runs a checked normal batch through `call` (a plugin's vtable entry, or the same trampoline
/// compiled into the host) and turns its status into a result. Lengths are checked by the
/// caller.
fn run_normal_batch(
    name: &str,
    b: NormalBatch<'_>,
    call: impl FnOnce(&FfiNormalBatch, &mut BatchFault) -> Result<BatchStatus, RString>,
) -> Result<(), LawError> {
    let n = b.force.len();
    let ffi = FfiNormalBatch {
        n,
        slots: b.slots,
        delta: b.delta.as_ptr(),
        rate: b.rate.as_ptr(),
        mass: b.mass.as_ptr(),
        radius: b.radius.as_ptr(),
        history: b.history.as_mut_ptr(),
        force: b.force.as_mut_ptr(),
    };
    let mut fault = BatchFault::default();
    let st = call(&ffi, &mut fault)
        .map_err(|msg| LawError::new(ErrorKind::Panic, format!("contact law '{name}' panicked: {msg}")))?;
    if st == BatchStatus::Ok {
        return Ok(());
    }
    let i = fault.index.min(n - 1);
    let c = Contact {
        delta: b.delta[i],
        rate: b.rate[i],
        mass: b.mass[i],
        radius: b.radius[i],
    };
    if st == BatchStatus::NonFiniteOutput {
        return Err(normal_non_finite(name, b.force[i], c));
    }
    let v = match fault.field {
        BatchFault::DELTA => c.delta,
        BatchFault::RATE => c.rate,
        BatchFault::MASS => c.mass,
        _ => c.radius,
    };
    Err(bad_input("contact", name, fault.field, i, v))
}

fn check_normal_lengths(name: &str, slots: usize, b: &NormalBatch<'_>) -> Result<(), LawError> {
    let n = b.force.len();
    if b.delta.len() != n || b.rate.len() != n || b.mass.len() != n || b.radius.len() != n {
        return Err(length_error(
            "force_batch",
            format!(
                "delta {}, rate {}, mass {}, radius {}, force {}",
                b.delta.len(),
                b.rate.len(),
                b.mass.len(),
                b.radius.len(),
                n
            ),
        ));
    }
    if b.slots != slots || b.history.len() != n * slots {
        return Err(length_error(
            "force_batch",
            format!(
                "history has {} values for {n} contacts of {} slots (law '{name}' keeps {slots})",
                b.history.len(),
                b.slots,
            ),
        ));
    }
    Ok(())
}

/// A contact law compiled into the host (tests, benchmarks, baselines), bound to a pair of
/// materials, and called through the very trampoline a plugin exports: the same input and
/// output checks, statically dispatched.
pub struct StaticContact<B>(StaticModel<Normal, B>);

impl<B: crate::law::BoundContact> StaticContact<B> {
    /// Binds law `L` (configured as `law`) to `materials`.
    pub fn bind<L: crate::law::ContactLaw<Bound = B>>(
        law: &L,
        materials: &MaterialPair,
    ) -> Result<Self, LawError> {
        Ok(StaticContact(StaticModel::bind(law, materials)?))
    }

    /// The law's name.
    pub fn name(&self) -> &str {
        self.0.name()
    }

    /// History slots per contact.
    pub fn history_slots(&self) -> usize {
        self.0.history_slots()
    }

    /// The bound law.
    pub fn law(&self) -> &B {
        self.0.law()
    }

    /// As [`ContactModelHandle::force_batch`].
    #[inline]
    pub fn force_batch(&self, b: NormalBatch<'_>) -> Result<(), LawError> {
        check_normal_lengths(self.name(), self.history_slots(), &b)?;
        self.0
            .batch(
                NormalCall {
                    batch: b,
                    reach: None,
                },
                EnergyOut::none(),
            )
            .map(|_| ())
    }

    /// As [`ContactModelHandle::force_batch_with`].
    pub fn force_batch_with(
        &self,
        b: NormalBatch<'_>,
        reach: Option<&mut [f64]>,
        energy: EnergyOut<'_>,
    ) -> Result<bool, LawError> {
        check_normal_lengths(self.name(), self.history_slots(), &b)?;
        self.0.batch(NormalCall { batch: b, reach }, energy)
    }
}

/// A contact law bound to a pair of materials: the hot path, per-contact geometry and history,
/// every input and output checked.
pub struct ContactModelHandle {
    inner: ModelInner,
    name: String,
    slots: usize,
}

impl ContactModelHandle {
    /// The law's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// History slots per contact.
    pub fn history_slots(&self) -> usize {
        self.slots
    }

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
        check_normal_lengths(&self.name, self.slots, &b)?;
        match &self.inner {
            ModelInner::V2(m) => run_normal_batch(&self.name, b, |ffi, fault| unsafe {
                match (m.vtable.force_batch)(m.obj, ffi, fault) {
                    BatchStatus::Panic => Err((m.vtable.take_panic)()),
                    st => Ok(st),
                }
            }),
            ModelInner::V1 { law, young } => self.force_batch_v1(law, *young, b),
            ModelInner::V3(m) => m
                .batch(
                    NormalCall {
                        batch: b,
                        reach: None,
                    },
                    EnergyOut::none(),
                )
                .map(|_| ()),
        }
    }

    /// As [`ContactModelHandle::force_batch`], with each contact's reach (m, ≥ 0: the contact
    /// ends at δ < −reach) written to `reach` and the energy outputs `energy` asks for:
    /// `Ok(true)` when those were written. A law of a plugin older than sdk 0.3 has reach 0 and
    /// reports energy as not available (`Ok(false)`).
    pub fn force_batch_with(
        &self,
        b: NormalBatch<'_>,
        reach: Option<&mut [f64]>,
        energy: EnergyOut<'_>,
    ) -> Result<bool, LawError> {
        match &self.inner {
            ModelInner::V3(m) => {
                check_normal_lengths(&self.name, self.slots, &b)?;
                m.batch(NormalCall { batch: b, reach }, energy)
            }
            _ => {
                let n = b.force.len();
                if reach.as_ref().is_some_and(|r| r.len() != n) {
                    return Err(length_error("force_batch", format!("reach must hold {n} values")));
                }
                self.force_batch(b)?;
                if let Some(r) = reach {
                    r.fill(0.0);
                }
                Ok(false)
            }
        }
    }

    /// A 0.1 law: inputs checked here (0.1 plugins do not), then one 0.1 batch call per run of
    /// contacts with the same geometry.
    fn force_batch_v1(&self, law: &V1Law, young: f64, b: NormalBatch<'_>) -> Result<(), LawError> {
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
        let mut out = [0.0];
        self.force_batch(NormalBatch {
            delta: &[c.delta],
            rate: &[c.rate],
            mass: &[c.mass],
            radius: &[c.radius],
            slots: self.slots,
            history,
            force: &mut out,
        })?;
        Ok(out[0])
    }

    /// The law's derived constants for a contact of effective `mass` (kg) and `radius` (m).
    pub fn coefficients(&self, mass: f64, radius: f64) -> Result<Vec<Coefficient>, LawError> {
        match &self.inner {
            ModelInner::V2(m) => match unsafe { (m.vtable.coefficients)(m.obj, mass, radius) } {
                RResult::ROk(v) => Ok(v.into_vec()),
                RResult::RErr(e) => Err(e.into()),
            },
            ModelInner::V3(m) => m.coefficients(mass, radius),
            ModelInner::V1 { law, young } => {
                let b = law.bound(mass, radius, *young)?;
                match unsafe { (b.ffi.vtable.coefficients)(b.ffi.obj) } {
                    RResult::ROk(v) => Ok(v.into_vec()),
                    RResult::RErr(e) => Err(e.into()),
                }
            }
        }
    }
}

impl Drop for ContactModelHandle {
    fn drop(&mut self) {
        if let ModelInner::V2(m) = &self.inner {
            unsafe { (m.vtable.drop)(m.obj) }
        }
    }
}
