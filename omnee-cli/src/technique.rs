//! The techniques for placing the once-more vertex `x1`, shared by `render`,
//! `probe`, `estimate` and `samples`, and the `auto` choice between them.

use crate::rng::Rng;
use clap::ValueEnum;
use omnee_core::Real;
use omnee_core::medium::{Homogeneous, Region};
use omnee_core::mis::OmneeMis;
use omnee_core::phase::PhaseFunction;
use omnee_core::sampling::{
    Connection, Directions, Distance, Equiangular, Omnee, Sample, Technique as _,
};

/// A technique for the once-more term as asked for (`--technique`, the
/// scene's `render.technique`): one of the four, or `auto`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Technique {
    /// the deflection from the phase function, then x1 on the circumcircle arc
    Omnee,
    /// a direction from the receiver, then the distance equiangular towards the light
    Equiangular,
    /// a direction from the receiver, then an exponential free-flight distance
    Distance,
    /// OMNEE over the whole range, and for 5 % of the connections one more, equiangular, vertex kept behind theta = 3 pi/4 (multi-sample MIS, balance heuristic there)
    Mis,
    /// OMNEE, or mis in a thin medium with a broad phase function; says what it picked and why
    Auto,
}

crate::names::display_by_name!(Technique);

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
    pub fn name(self) -> String {
        Technique::from(self).to_string()
    }
}

impl From<Tech> for Technique {
    fn from(tech: Tech) -> Self {
        match tech {
            Tech::Omnee => Technique::Omnee,
            Tech::Equiangular => Technique::Equiangular,
            Tech::Distance => Technique::Distance,
            Tech::Mis => Technique::Mis,
        }
    }
}

/// The resolved choice: the technique and, for `auto`, why.
#[derive(Clone, Debug)]
pub struct Choice {
    /// The technique used.
    pub tech: Tech,
    /// What was asked for.
    pub requested: Technique,
    /// For `auto`: the reason, in a sentence.
    pub reason: Option<String>,
}

/// Resolves `requested`; `auto` picks from the phase function's mean
/// cosine `g` and the optical thickness `tau = σt · distance` of a typical
/// connection ([`auto`]).
pub fn choose(requested: Technique, g: f64, tau: f64) -> Choice {
    let (tech, reason) = match requested {
        Technique::Omnee => (Tech::Omnee, None),
        Technique::Equiangular => (Tech::Equiangular, None),
        Technique::Distance => (Tech::Distance, None),
        Technique::Mis => (Tech::Mis, None),
        Technique::Auto => {
            let (tech, reason) = auto(g, tau);
            (tech, Some(reason))
        }
    };
    Choice {
        tech,
        requested,
        reason,
    }
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

/// What every technique needs besides the connection and the ray
/// directions: the phase function at `x1`, where the medium is, and its
/// extinction σt (distance sampling's free-flight coefficient), checked once
/// by [`Setup::new`].
#[derive(Clone, Copy, Debug)]
pub struct Setup<F: Real, P> {
    phase: P,
    region: Region<F>,
    sigma_t: F,
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

impl<F: Real, P: PhaseFunction<F>> Setup<F, P> {
    /// The setup for `phase` in `region` with extinction `sigma_t`: σt must
    /// be finite and non-negative (the core's rule for an extinction
    /// coefficient, which distance sampling applies to its free-flight
    /// coefficient).
    pub fn new(phase: P, region: Region<F>, sigma_t: F) -> Result<Self, omnee_core::Error> {
        Homogeneous::from_extinction(F::ZERO, sigma_t)?;
        Ok(Self {
            phase,
            region,
            sigma_t,
        })
    }

    /// The phase function at `x1`.
    pub fn phase(&self) -> &P {
        &self.phase
    }

    /// One draw for `connection` (whose θmax is the integrand's) with `tech`
    /// and ray `directions` from the receiver (equiangular, distance, MIS):
    /// three uniform numbers from `rng`, six for `mis`.
    pub fn sample(
        &self,
        tech: Tech,
        connection: Connection<F>,
        directions: Directions<F>,
        rng: &mut Rng,
    ) -> Draw<F> {
        let [a, b, c] = rng.uniform3::<F>();
        let one = |s: Option<Sample<F>>| Draw {
            u: [a, b, c, F::ZERO, F::ZERO, F::ZERO],
            vertices: [s, None],
        };
        let phase = &self.phase;
        match tech {
            Tech::Omnee => one(Omnee::new(connection, phase).sample([a, b, c])),
            Tech::Equiangular => {
                one(Equiangular::new(connection, phase, directions, self.region).sample([a, b, c]))
            }
            Tech::Distance => {
                match Distance::new(connection, phase, directions, self.region, self.sigma_t) {
                    Ok(distance) => one(distance.sample([a, b, c])),
                    Err(_) => unreachable!("Setup::new checked sigma_t by the same rule"),
                }
            }
            Tech::Mis => {
                let [d, e, f] = rng.uniform3::<F>();
                let u = [a, b, c, d, e, f];
                let equiangular = Equiangular::new(connection, phase, directions, self.region);
                let mis = OmneeMis::recommended(Omnee::new(connection, phase), &equiangular);
                Draw {
                    u,
                    vertices: mis.sample(u),
                }
            }
        }
    }
}

/// How the once-more term is estimated.
#[derive(Clone, Copy, Debug)]
pub struct OnceMore {
    /// The technique for `x1`.
    pub tech: Tech,
    /// The integrand's restriction θ < θmax.
    pub theta_max: f32,
}
