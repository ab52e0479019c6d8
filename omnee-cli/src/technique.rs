//! The techniques for placing the once-more vertex `x1`, shared by `render`,
//! `probe`, `estimate` and `samples`, and the `auto` choice between them.

use crate::error::{CliError, Result};
use crate::rng::Rng;
use omnee_core::Real;
use omnee_core::medium::Region;
use omnee_core::mis::OmneeMis;
use omnee_core::phase::PhaseFunction;
use omnee_core::sampling::{
    Connection, Directions, Distance, Equiangular, Omnee, Sample, Technique,
};

/// A technique for the once-more term.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tech {
    /// OMNEE: the deflection from the phase function, then the circumcircle
    /// arc (restricted to the integrand's θmax).
    Omnee,
    /// Equiangular distance along a direction from the receiver.
    Equiangular,
    /// Exponential free-flight distance along a direction from the receiver.
    Distance,
    /// OMNEE over the integrand's whole range, and with probability 0.05 an
    /// equiangular vertex behind the backward cone θ ≥ 3π/4
    /// ([`OmneeMis::recommended`]): MIS that covers backward scattering where
    /// OMNEE's weight grows.
    Mis,
}

impl Tech {
    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Tech::Omnee => "omnee",
            Tech::Equiangular => "equiangular",
            Tech::Distance => "distance",
            Tech::Mis => "mis",
        }
    }
}

/// The resolved choice: the technique and, for `auto`, why.
#[derive(Clone, Debug)]
pub struct Choice {
    /// The technique used.
    pub tech: Tech,
    /// What was asked for (`auto` or the technique's name).
    pub requested: String,
    /// For `auto`: the reason, in a sentence.
    pub reason: Option<String>,
}

/// Resolves a technique name; `auto` picks from the phase function's mean
/// cosine `g` and the optical thickness `tau = σt · distance` of a typical
/// connection ([`auto`]).
pub fn choose(field: &str, name: &str, g: f64, tau: f64) -> Result<Choice> {
    let tech = match name {
        "omnee" => Tech::Omnee,
        "equiangular" => Tech::Equiangular,
        "distance" => Tech::Distance,
        "mis" => Tech::Mis,
        "auto" => {
            let (tech, reason) = auto(g, tau);
            return Ok(Choice {
                tech,
                requested: "auto".into(),
                reason: Some(reason),
            });
        }
        _ => {
            return Err(CliError::Input(format!(
                "{field} = \"{name}\" is not a technique; allowed: omnee, equiangular, distance, mis, auto"
            )));
        }
    };
    Ok(Choice {
        tech,
        requested: name.into(),
        reason: None,
    })
}

/// The optical thickness below which `auto` adds equiangular sampling
/// behind the backward cone for broad phase functions.
pub const AUTO_THIN: f64 = 0.2;

/// `auto`: OMNEE over the whole range, unless the medium barely attenuates
/// (`tau` < [`AUTO_THIN`]) and the phase function is not forward-peaked
/// (`g` < 0.3); then [`Tech::Mis`]. OMNEE's weight θ/(s sin θ) is bounded by
/// attenuation behind the cone (its variance grows like ln(1/τ) as τ → 0) and
/// is near 1/s for a forward peak; equiangular sampling alone is never
/// chosen, its variance is infinite for a point-like `x0` (the weight grows
/// like 1/D as the ray passes `x0`).
pub fn auto(g: f64, tau: f64) -> (Tech, String) {
    if g >= 0.3 {
        (
            Tech::Omnee,
            format!(
                "the phase function is forward-peaked (mean cosine {g:.3} >= 0.3): OMNEE draws the deflection \
                 from it, and its weight theta/(s sin theta) stays near 1/s"
            ),
        )
    } else if tau >= AUTO_THIN {
        (
            Tech::Omnee,
            format!(
                "the medium attenuates along a typical connection (tau = {tau:.3} >= {AUTO_THIN}): attenuation \
                 bounds OMNEE's weight theta/(s sin theta) for backward deflections (mean cosine {g:.3})"
            ),
        )
    } else {
        (
            Tech::Mis,
            format!(
                "the medium is optically thin (tau = {tau:.3} < {AUTO_THIN}) and the phase function not \
                 forward-peaked (mean cosine {g:.3}): OMNEE's weight grows like 1/(pi - theta) unchecked, so \
                 equiangular sampling joins it behind theta = 3 pi/4"
            ),
        )
    }
}

/// Everything a technique needs besides the connection.
pub struct Setup<'p, F: Real, P> {
    /// The phase function at `x1`.
    pub phase: &'p P,
    /// Ray directions from the receiver (equiangular, distance, MIS).
    pub directions: Directions<F>,
    /// Where the medium is.
    pub region: Region<F>,
    /// Extinction σt (the free-flight coefficient of distance sampling).
    pub sigma_t: F,
}

/// One draw of a technique: the uniform numbers it took and its vertices,
/// the technique's own and, for [`Tech::Mis`], the companion's (from
/// `u[3..6]`). The once-more estimate is the sum of `f_c · weight` over them.
#[derive(Clone, Copy, Debug)]
pub struct Draw<F: Real> {
    /// The uniform numbers: `u[0..3]` for the first vertex, `u[3..6]` for the
    /// companion's (drawn by `mis` only, else 0).
    pub u: [F; 6],
    /// The vertices; `None` where the numbers give no vertex.
    pub vertices: [Option<Sample<F>>; 2],
}

impl<F: Real, P: PhaseFunction<F>> Setup<'_, F, P> {
    /// One draw for `connection` (whose θmax is the integrand's) with `tech`:
    /// three uniform numbers from `rng`, six for `mis`.
    pub fn sample(&self, tech: Tech, connection: Connection<F>, rng: &mut Rng) -> Draw<F> {
        let [a, b, c] = rng.uniform3::<F>();
        let one = |s: Option<Sample<F>>| Draw {
            u: [a, b, c, F::ZERO, F::ZERO, F::ZERO],
            vertices: [s, None],
        };
        match tech {
            Tech::Omnee => one(Omnee::new(connection, self.phase).sample([a, b, c])),
            Tech::Equiangular => one(self.equiangular(connection).sample([a, b, c])),
            Tech::Distance => one(Distance::new(
                connection,
                self.phase,
                self.directions,
                self.region,
                self.sigma_t,
            )
            .ok()
            .and_then(|t| t.sample([a, b, c]))),
            Tech::Mis => {
                let [d, e, f] = rng.uniform3::<F>();
                let u = [a, b, c, d, e, f];
                let equiangular = self.equiangular(connection);
                let mis = OmneeMis::recommended(Omnee::new(connection, self.phase), &equiangular);
                Draw {
                    u,
                    vertices: mis.sample(u),
                }
            }
        }
    }

    fn equiangular(&self, connection: Connection<F>) -> Equiangular<F, &P> {
        Equiangular::new(connection, self.phase, self.directions, self.region)
    }
}
