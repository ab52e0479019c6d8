//! Option parsers (for clap's `value_parser`) and checks that several
//! subcommands share.

use crate::error::{CliError, Result};

/// `X,Y,Z` with finite components.
pub fn parse_vec3(s: &str) -> std::result::Result<[f64; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let bad =
        || format!("\"{s}\" is not a vector; allowed: three comma-separated finite numbers X,Y,Z");
    if parts.len() != 3 {
        return Err(bad());
    }
    let mut v = [0.0; 3];
    for (slot, p) in v.iter_mut().zip(parts) {
        *slot = p.parse::<f64>().map_err(|_| bad())?;
        if !slot.is_finite() {
            return Err(bad());
        }
    }
    Ok(v)
}

/// `WIDTHxHEIGHT`, each in [1, 16384].
pub fn parse_resolution(s: &str) -> std::result::Result<(u32, u32), String> {
    let bad = || format!("\"{s}\" is not a resolution; allowed: WIDTHxHEIGHT, each in [1, 16384]");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    );
    if !(1..=16384).contains(&w) || !(1..=16384).contains(&h) {
        return Err(bad());
    }
    Ok((w, h))
}

/// `A,B,C,D` of non-negative integers.
pub fn parse_u32x4(s: &str) -> std::result::Result<[u32; 4], String> {
    let bad = || format!("\"{s}\" is not a window; allowed: X0,Y0,X1,Y1 (non-negative integers)");
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 4 {
        return Err(bad());
    }
    let mut v = [0u32; 4];
    for (slot, p) in v.iter_mut().zip(parts) {
        *slot = p.parse().map_err(|_| bad())?;
    }
    Ok(v)
}

/// A number of samples or draws in `[1, 2^40]`.
pub fn check_count(field: &str, n: u64) -> Result<u64> {
    if (1..=1u64 << 40).contains(&n) {
        Ok(n)
    } else {
        Err(CliError::range(field, n, "[1, 2^40]"))
    }
}

/// `n / |n|`, naming `field` when `n` is zero.
pub fn unit_normal(field: &str, n: [f64; 3]) -> Result<[f64; 3]> {
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if !(len > 0.0) {
        return Err(CliError::Input(format!(
            "{field} = {},{},{} has zero length; allowed: any non-zero vector",
            n[0], n[1], n[2]
        )));
    }
    Ok([n[0] / len, n[1] / len, n[2] / len])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parsers_accept_their_forms_and_name_them_otherwise() {
        assert_eq!(parse_vec3("1, -2,3e1"), Ok([1.0, -2.0, 30.0]));
        assert!(parse_vec3("1,2").unwrap_err().contains("X,Y,Z"));
        assert!(parse_vec3("1,2,inf").is_err());
        assert_eq!(parse_resolution("64x48"), Ok((64, 48)));
        assert!(parse_resolution("0x48").unwrap_err().contains("[1, 16384]"));
        assert_eq!(parse_u32x4("0,1,2,3"), Ok([0, 1, 2, 3]));
        assert!(parse_u32x4("0,1,2,-3").is_err());
        assert!(check_count("--samples", 0).is_err() && check_count("--samples", 1).is_ok());
        assert_eq!(unit_normal("n", [0.0, 0.0, 2.0]).unwrap(), [0.0, 0.0, 1.0]);
    }
}
