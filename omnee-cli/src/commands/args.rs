//! Option parsers (for clap's `value_parser`) and the options that several
//! subcommands share.

use crate::named::closed;
use clap::Args;
use omnee_core::method::Choice;
use omnee_render::point::problem::{Precision, Problem};
use omnee_render::vertices::{DEFAULT_MAX_VERTICES, VertexNumber};
use omnee_render::{RenderError, Result};

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

/// `auto` or an integer `K` (its range is the library's to check).
pub fn parse_vertices(s: &str) -> std::result::Result<VertexNumber, String> {
    VertexNumber::parse(s, DEFAULT_MAX_VERTICES)
}

/// `vertices` with `--max-vertices` applied to `auto`; an error for a
/// fixed number.
pub fn with_max(vertices: VertexNumber, max: Option<usize>) -> Result<VertexNumber> {
    match (vertices, max) {
        (VertexNumber::Auto { .. }, Some(max)) => Ok(VertexNumber::Auto { max }),
        (VertexNumber::Fixed(_), Some(max)) => Err(RenderError::Input(format!(
            "--max-vertices = {max} applies to --vertices auto only; allowed: leave it out"
        ))),
        (v, None) => Ok(v),
    }
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

/// The options that state the point-to-point problem of `estimate` and
/// `samples` (the library's [`Problem`]).
#[derive(Args, Debug)]
pub struct ProblemArgs {
    /// The unit-intensity point light x0 = X,Y,Z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub x0: [f64; 3],
    /// The point receiver x2 = X,Y,Z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub x2: [f64; 3],
    /// Phase function spec (see below).
    #[arg(long, default_value = "iso")]
    pub phase: String,
    /// Scattering coefficient (1/m).
    #[arg(long, allow_hyphen_values = true)]
    pub sigma_s: f64,
    /// Extinction coefficient (1/m), at least sigma-s.
    #[arg(long, allow_hyphen_values = true)]
    pub sigma_t: f64,
    /// The integrand is restricted to theta < THETA_MAX (radians, (0, pi]).
    #[arg(long, allow_hyphen_values = true, default_value_t = std::f64::consts::PI)]
    pub theta_max: f64,
    /// A receiver cosine max(0, n . (x1 - x2)/d2) about this normal.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub receiver_normal: Option<[f64; 3]>,
    /// Technique for x1.
    #[arg(long, value_parser = closed::<Choice>(), default_value = "auto")]
    pub technique: Choice,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Arithmetic precision of the techniques.
    #[arg(long, value_parser = closed::<Precision>(), default_value = "f32")]
    pub precision: Precision,
    /// Phase function at x0 (a scattering vertex): light arriving along --x0-incoming leaves x0 with this lobe [spec as --phase]
    #[arg(long)]
    pub x0_phase: Option<String>,
    /// Propagation direction X,Y,Z of the light arriving at x0 (normalised here)
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub x0_incoming: Option<[f64; 3]>,
    /// Scattering vertices between x0 and x2: 1 (the once-more integral, by --technique), K in [2, 32] (bridges of K vertices: I_K), or auto (the sum of I_K over K = 1 ... --max-vertices, K drawn per sample)
    #[arg(long, value_parser = parse_vertices, default_value = "1", value_name = "K|auto", allow_hyphen_values = true)]
    pub vertices: VertexNumber,
    /// The largest K of --vertices auto [default: 8]
    #[arg(long, value_name = "K")]
    pub max_vertices: Option<usize>,
}

impl ProblemArgs {
    /// The problem these options state.
    pub fn problem(&self) -> Result<Problem> {
        Ok(Problem {
            x0: self.x0,
            x2: self.x2,
            phase: self.phase.clone(),
            sigma_s: self.sigma_s,
            sigma_t: self.sigma_t,
            theta_max: self.theta_max,
            receiver_normal: self.receiver_normal,
            technique: self.technique,
            seed: self.seed,
            precision: self.precision,
            x0_phase: self.x0_phase.clone(),
            x0_incoming: self.x0_incoming,
            vertices: with_max(self.vertices, self.max_vertices)?,
        })
    }
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
        assert_eq!(parse_vertices("auto"), Ok(VertexNumber::Auto { max: 8 }));
        assert_eq!(parse_vertices("3"), Ok(VertexNumber::Fixed(3)));
        assert!(parse_vertices("-3").is_err());
        assert_eq!(
            with_max(VertexNumber::Auto { max: 8 }, Some(4)).unwrap(),
            VertexNumber::Auto { max: 4 }
        );
        let e = with_max(VertexNumber::Fixed(2), Some(4))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("--max-vertices = 4"), "{e}");
    }
}
