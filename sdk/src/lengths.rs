//! The lengths of a batch's arrays, which every call checks before a law sees them.

use crate::error::{ErrorKind, LawError};

/// The error of a batch call `what` whose arrays disagree in length (`detail` gives them).
pub(crate) fn length_error(what: &str, detail: String) -> LawError {
    LawError::new(
        ErrorKind::Other,
        format!("{what}: the batch's arrays disagree in length: {detail}"),
    )
}

/// The lengths of the arrays of a batch for `call` ("force_batch", ...): its inputs (`inputs`
/// names them, `lens` gives them), its output (`output`, of `n` values: the number of contacts)
/// and its history (`slots` per contact, `history` values in all).
pub(crate) struct BatchLengths<const N: usize> {
    pub(crate) call: &'static str,
    pub(crate) inputs: &'static str,
    pub(crate) lens: [usize; N],
    pub(crate) output: &'static str,
    pub(crate) n: usize,
    pub(crate) slots: usize,
    pub(crate) history: usize,
    /// The length of the batch's normal contexts (sdk 0.4), which are optional: `n`, or 0 for
    /// none (the defaults); 0 for a batch without them.
    pub(crate) context: usize,
}

impl<const N: usize> BatchLengths<N> {
    /// Checks them for the `kind` law `name`, which keeps `slots` history values per contact:
    /// every input one value per contact, the history `n × slots`.
    #[inline(always)]
    pub(crate) fn check(&self, kind: &str, name: &str, slots: usize) -> Result<(), LawError> {
        let n = self.n;
        // every call of a host's step passes here: one branch-free test, the message built out
        // of line only when it fails
        let inputs = self.lens.iter().fold(true, |ok, &l| ok & (l == n));
        let context = (self.context == 0) | (self.context == n);
        if inputs & context & (self.slots == slots) & (self.history == n * slots) {
            return Ok(());
        }
        self.refuse(kind, name, slots)
    }

    /// The error of [`BatchLengths::check`] when it fails.
    #[cold]
    #[inline(never)]
    fn refuse(&self, kind: &str, name: &str, slots: usize) -> Result<(), LawError> {
        let n = self.n;
        let call = || format!("{kind} {}", self.call);
        if self.lens.iter().any(|&l| l != n) {
            return Err(length_error(
                &call(),
                format!("{} {:?}, {} {n}", self.inputs, self.lens, self.output),
            ));
        }
        if self.context != 0 && self.context != n {
            return Err(length_error(
                &call(),
                format!(
                    "context has {} values for {n} contacts: give one per contact, or none for the defaults",
                    self.context
                ),
            ));
        }
        if self.slots != slots || self.history != n * slots {
            return Err(length_error(
                &call(),
                format!(
                    "history has {} values for {n} contacts of {} slots (law '{name}' keeps {slots})",
                    self.history, self.slots
                ),
            ));
        }
        Ok(())
    }
}
