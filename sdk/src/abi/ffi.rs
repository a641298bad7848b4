//! The stable-ABI mirrors of the plain types that law authors and hosts use ([`LawInfo`],
//! [`ParamSpec`], [`ParamValue`], [`HistorySlot`], [`Coefficient`], [`CalibrationTarget`]), with
//! abi_stable's `RString`, `RVec` and `ROption` in place of `String`, `Vec` and `Option`, and
//! the conversions both ways. Only the export macro and the loader see them.
//!
//! Each mirror has the name of its plain type: abi_stable's layout check compares type names,
//! and sdk 0.1 and 0.2 plugins recorded these layouts under these names (their `LawInfo` is the
//! frozen one of [`v1`](super::v1) or [`v2`](super::v2)). Their layout must never change.

use crate::law::{EndCriterion, LawKind};
use crate::params::Range;
use abi_stable::{
    std_types::{ROption, RString, RVec},
    StableAbi,
};

/// A field of a mirror and the field of its plain type.
trait Field<P> {
    fn to_ffi(p: &P) -> Self;
    fn to_plain(self) -> P;
}

impl<T: Copy> Field<T> for T {
    fn to_ffi(p: &T) -> T {
        *p
    }
    fn to_plain(self) -> T {
        self
    }
}

impl Field<String> for RString {
    fn to_ffi(p: &String) -> RString {
        p.as_str().into()
    }
    fn to_plain(self) -> String {
        self.into_string()
    }
}

impl Field<Option<f64>> for ROption<f64> {
    fn to_ffi(p: &Option<f64>) -> ROption<f64> {
        (*p).into()
    }
    fn to_plain(self) -> Option<f64> {
        self.into_option()
    }
}

impl Field<Option<EndCriterion>> for ROption<EndCriterion> {
    fn to_ffi(p: &Option<EndCriterion>) -> ROption<EndCriterion> {
        (*p).into()
    }
    fn to_plain(self) -> Option<EndCriterion> {
        self.into_option()
    }
}

impl<F, P> Field<Vec<P>> for RVec<F>
where
    F: for<'a> From<&'a P>,
    P: From<F>,
{
    fn to_ffi(p: &Vec<P>) -> RVec<F> {
        p.iter().map(F::from).collect()
    }
    fn to_plain(self) -> Vec<P> {
        self.into_iter().map(P::from).collect()
    }
}

/// Declares the mirror of plain type `crate::$name` and the conversions both ways.
macro_rules! mirror {
    ($(#[$doc:meta])* $name:ident { $($(#[$fdoc:meta])* $field:ident: $ty:ty,)* }) => {
        $(#[$doc])*
        #[repr(C)]
        #[derive(StableAbi, Debug, Clone, PartialEq)]
        pub struct $name {
            $($(#[$fdoc])* pub $field: $ty,)*
        }

        impl From<&crate::$name> for $name {
            fn from(p: &crate::$name) -> $name {
                $name { $($field: Field::to_ffi(&p.$field),)* }
            }
        }

        impl From<$name> for crate::$name {
            fn from(f: $name) -> crate::$name {
                crate::$name { $($field: Field::to_plain(f.$field),)* }
            }
        }
    };
}

mirror! {
    /// The mirror of [`crate::LawInfo`] (sdk 0.4).
    LawInfo {
        /// Name.
        name: RString,
        /// Kind.
        kind: LawKind,
        /// One line.
        summary: RString,
        /// Documentation.
        doc: RString,
        /// Parameter schema.
        params: RVec<ParamSpec>,
        /// End criterion of a contact law.
        end_criterion: ROption<EndCriterion>,
        /// Per-contact history slots.
        history: RVec<HistorySlot>,
        /// Whether the law reads the normal law's context (sdk 0.4).
        reads_context: bool,
    }
}

mirror! {
    /// The mirror of [`crate::ParamSpec`] (unchanged since sdk 0.1).
    ParamSpec {
        /// Name.
        name: RString,
        /// SI unit.
        unit: RString,
        /// Default value, if any.
        default: ROption<f64>,
        /// Valid values.
        range: Range,
        /// One line.
        doc: RString,
    }
}

mirror! {
    /// The mirror of [`crate::ParamValue`] (unchanged since sdk 0.1).
    ParamValue {
        /// Name.
        name: RString,
        /// Value in the unit of the schema.
        value: f64,
    }
}

mirror! {
    /// The mirror of [`crate::HistorySlot`] (unchanged since sdk 0.2).
    HistorySlot {
        /// Name.
        name: RString,
        /// SI unit.
        unit: RString,
        /// One line.
        doc: RString,
    }
}

mirror! {
    /// The mirror of [`crate::Coefficient`] (unchanged since sdk 0.1).
    Coefficient {
        /// Symbol.
        name: RString,
        /// SI unit.
        unit: RString,
        /// Value in `unit`.
        value: f64,
        /// One line.
        doc: RString,
    }
}

mirror! {
    /// The mirror of [`crate::CalibrationTarget`] (unchanged since sdk 0.1).
    CalibrationTarget {
        /// Measured restitution.
        restitution: f64,
        /// Measured contact time (s), if any.
        contact_time: ROption<f64>,
        /// Normal impact speed (m/s), if known.
        impact_speed: ROption<f64>,
        /// The end-of-contact criterion of the measurement.
        end: EndCriterion,
    }
}

impl Copy for CalibrationTarget {}

/// Plain values as mirrors, for a slice crossing the boundary.
pub(crate) fn to_ffi<'a, P: 'a, F: From<&'a P>>(v: &'a [P]) -> RVec<F> {
    v.iter().map(F::from).collect()
}

/// Mirrors as plain values.
pub(crate) fn to_plain<F, P: From<F>>(v: RVec<F>) -> Vec<P> {
    v.into_iter().map(P::from).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mirrors_round_trip() {
        let info = crate::LawInfo {
            name: "x".into(),
            kind: LawKind::Contact,
            summary: "s".into(),
            doc: "d".into(),
            params: vec![
                crate::ParamSpec::new("k", "N/m", 2.0, Range::positive(), "k"),
                crate::ParamSpec::derived("c", "1", Range::non_negative(), "c"),
            ],
            end_criterion: Some(EndCriterion::Force),
            history: vec![crate::HistorySlot {
                name: "h".into(),
                unit: "m".into(),
                doc: "h".into(),
            }],
            reads_context: true,
        };
        assert_eq!(crate::LawInfo::from(LawInfo::from(&info)), info);
        let t = crate::CalibrationTarget {
            restitution: 0.5,
            contact_time: Some(1e-3),
            impact_speed: None,
            end: EndCriterion::Overlap,
        };
        assert_eq!(crate::CalibrationTarget::from(CalibrationTarget::from(&t)), t);
    }
}
