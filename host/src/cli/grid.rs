//! Parameter grids for sweeps: `a:b:n[:log|lin]` or a comma-separated list.

/// Why a grid specification is invalid.
#[derive(Debug, thiserror::Error)]
#[error(
    "invalid grid '{spec}': {why} (expected START:STOP:COUNT[:log|lin] or a comma-separated list of numbers)"
)]
pub struct GridError {
    /// The specification.
    pub spec: String,
    /// What is wrong.
    pub why: String,
}

/// Parses a grid. `log` spacing (the default when both ends are positive and span more than a
/// decade) needs positive ends.
pub fn parse_grid(spec: &str) -> Result<Vec<f64>, GridError> {
    let err = |why: &str| GridError {
        spec: spec.to_string(),
        why: why.to_string(),
    };
    let num = |s: &str| -> Result<f64, GridError> {
        let v: f64 = s
            .trim()
            .parse()
            .map_err(|_| err(&format!("'{s}' is not a number")))?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(err(&format!("{v} is not finite")))
        }
    };
    if spec.contains(',') || !spec.contains(':') {
        return spec.split(',').map(num).collect();
    }
    let parts: Vec<&str> = spec.split(':').collect();
    if parts.len() < 3 || parts.len() > 4 {
        return Err(err("wrong number of ':' fields"));
    }
    let (a, b) = (num(parts[0])?, num(parts[1])?);
    let n: usize = parts[2]
        .trim()
        .parse()
        .map_err(|_| err("COUNT must be a whole number"))?;
    if n == 0 || n > 1_000_000 {
        return Err(err("COUNT must be between 1 and 1000000"));
    }
    let log = match parts.get(3).map(|s| s.trim()) {
        Some("log") => true,
        Some("lin") => false,
        Some(o) => return Err(err(&format!("unknown spacing '{o}'"))),
        None => a > 0.0 && b > 0.0 && (b / a).abs().log10().abs() > 1.0,
    };
    if log && (a <= 0.0 || b <= 0.0) {
        return Err(err("log spacing needs positive START and STOP"));
    }
    if n == 1 {
        return Ok(vec![a]);
    }
    Ok((0..n)
        .map(|i| {
            let f = i as f64 / (n - 1) as f64;
            if log {
                (a.ln() + f * (b.ln() - a.ln())).exp()
            } else {
                a + f * (b - a)
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids() {
        assert_eq!(parse_grid("0.1,0.5").unwrap(), vec![0.1, 0.5]);
        assert_eq!(parse_grid("2").unwrap(), vec![2.0]);
        let g = parse_grid("1e-3:10:5").unwrap();
        assert_eq!(g.len(), 5);
        assert!((g[1] - 1e-2).abs() < 1e-15 && (g[4] - 10.0).abs() < 1e-12);
        assert_eq!(parse_grid("0:1:3:lin").unwrap(), vec![0.0, 0.5, 1.0]);
        assert!(parse_grid("0:1:3:log").is_err());
        assert!(parse_grid("1:2:x").is_err());
        assert!(parse_grid("a,b").is_err());
        assert!(parse_grid("1:nan:3").is_err());
    }
}
