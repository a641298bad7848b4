//! Which sdk a plugin or host is built against, and which series a host speaks.

/// The dashpot-sdk version a plugin or host is built against (`major.minor.patch`).
///
/// The override variable exists only so the test suite can build a deliberately incompatible
/// plugin; never set it otherwise.
pub const ABI_VERSION: &str = match option_env!("DASHPOT_SDK_FAKE_ABI_VERSION") {
    Some(v) => v,
    None => env!("CARGO_PKG_VERSION"),
};

/// The series of sdk version `v`: (major, 0), or (0, minor) while the major is 0.
pub(crate) fn series(v: &str) -> Option<(u64, u64)> {
    let mut it = v.split('.').map(|p| p.trim().parse::<u64>());
    let major = it.next()?.ok()?;
    let minor = it.next()?.ok()?;
    Some(if major == 0 { (0, minor) } else { (major, 0) })
}

/// Whether a plugin built against sdk `plugin` may be loaded by a host built against `host`:
/// the same series (the major version, or the minor while the major is 0), or, for a 0.4 host,
/// a plugin of sdk 0.1, 0.2 or 0.3 (spoken to through the frozen [`v1`](super::v1),
/// [`v2`](super::v2) and [`v3`](super::v3) types).
pub fn abi_compatible(host: &str, plugin: &str) -> bool {
    match (series(host), series(plugin)) {
        (Some(a), Some(b)) if a == b => true,
        (Some((0, 4)), Some((0, 1) | (0, 2) | (0, 3))) => true,
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn abi_compatibility_rule() {
        assert!(abi_compatible("0.4.0", "0.4.7"));
        assert!(abi_compatible("0.4.7", "0.4.0"));
        // a 0.4 host speaks 0.1, 0.2 and 0.3 through the frozen v1, v2 and v3 types; older
        // hosts cannot speak 0.4
        assert!(abi_compatible("0.4.0", "0.1.0"));
        assert!(abi_compatible("0.4.0", "0.2.5"));
        assert!(abi_compatible("0.4.0", "0.3.0"));
        assert!(!abi_compatible("0.3.0", "0.4.0"));
        assert!(!abi_compatible("0.2.0", "0.4.0"));
        assert!(!abi_compatible("0.4.0", "0.5.0"));
        assert!(!abi_compatible("0.4.0", "0.0.9"));
        assert!(!abi_compatible("0.4.0", "1.0.0"));
        assert!(abi_compatible("1.2.0", "1.0.3"));
        assert!(!abi_compatible("1.0.0", "2.0.0"));
        assert!(!abi_compatible("0.4.0", "garbage"));
    }
}
