//! The once-more technique as the CLI offers it: the core's [`Method`]s by
//! name and `auto`, which picks one for the medium and says why (from
//! docs/math.md §3.4 and the variances of §6). The draw itself is the
//! core's ([`omnee_core::method::Setup`]).

use clap::ValueEnum;
use omnee_core::method::Method;

/// A technique for the once-more term as asked for (`--technique`, the
/// scene's `render.technique`): one of the core's [`Method`]s (the same
/// names), or `auto`.
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

impl From<Method> for Technique {
    fn from(method: Method) -> Self {
        match method {
            Method::Omnee => Technique::Omnee,
            Method::Equiangular => Technique::Equiangular,
            Method::Distance => Technique::Distance,
            Method::Mis => Technique::Mis,
        }
    }
}

/// The resolved choice: the method and, for `auto`, why.
#[derive(Clone, Debug)]
pub struct Choice {
    /// The method used.
    pub method: Method,
    /// What was asked for.
    pub requested: Technique,
    /// For `auto`: the reason, in a sentence.
    pub reason: Option<String>,
}

/// Resolves `requested`; `auto` picks from the phase function's mean
/// cosine `g` and the optical thickness `tau = σt · distance` of a typical
/// connection ([`auto`]).
pub fn choose(requested: Technique, g: f64, tau: f64) -> Choice {
    let (method, reason) = match requested {
        Technique::Omnee => (Method::Omnee, None),
        Technique::Equiangular => (Method::Equiangular, None),
        Technique::Distance => (Method::Distance, None),
        Technique::Mis => (Method::Mis, None),
        Technique::Auto => {
            let (method, reason) = auto(g, tau);
            (method, Some(reason))
        }
    };
    Choice {
        method,
        requested,
        reason,
    }
}

/// The optical thickness below which `auto` adds equiangular sampling
/// behind the backward cone for broad phase functions.
pub const AUTO_THIN: f64 = 0.2;

/// `auto`: OMNEE over the whole range, unless the medium barely attenuates
/// (`tau` < [`AUTO_THIN`]) and the phase function is not forward-peaked
/// (`g` < 0.3); then [`Method::Mis`]. OMNEE's weight θ/(s sin θ) is bounded by
/// attenuation behind the cone (its variance grows like ln(1/τ) as τ → 0) and
/// is near 1/s for a forward peak; equiangular sampling alone is never
/// chosen, its variance is infinite for a point-like `x0` (the weight grows
/// like 1/D as the ray passes `x0`).
pub fn auto(g: f64, tau: f64) -> (Method, String) {
    if g >= 0.3 {
        (
            Method::Omnee,
            format!(
                "the phase function is forward-peaked (mean cosine {g:.3} >= 0.3): OMNEE draws the deflection \
                 from it, and its weight theta/(s sin theta) stays near 1/s"
            ),
        )
    } else if tau >= AUTO_THIN {
        (
            Method::Omnee,
            format!(
                "the medium attenuates along a typical connection (tau = {tau:.3} >= {AUTO_THIN}): attenuation \
                 bounds OMNEE's weight theta/(s sin theta) for backward deflections (mean cosine {g:.3})"
            ),
        )
    } else {
        (
            Method::Mis,
            format!(
                "the medium is optically thin (tau = {tau:.3} < {AUTO_THIN}) and the phase function not \
                 forward-peaked (mean cosine {g:.3}): OMNEE's weight grows like 1/(pi - theta) unchecked, so \
                 equiangular sampling joins it behind theta = 3 pi/4"
            ),
        )
    }
}

/// How the once-more term is estimated.
#[derive(Clone, Copy, Debug)]
pub struct OnceMore {
    /// The method for `x1`.
    pub method: Method,
    /// The integrand's restriction θ < θmax.
    pub theta_max: f32,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::names;

    #[test]
    fn the_methods_have_the_cores_names_and_auto_is_added() {
        for m in Method::ALL {
            assert_eq!(Technique::from(m).to_string(), m.name());
            assert_eq!(choose(Technique::from(m), 0.0, 0.0).method, m);
        }
        assert_eq!(
            names::allowed::<Technique>(),
            format!("{}, auto", Method::ALLOWED)
        );
    }

    #[test]
    fn auto_picks_omnee_unless_thin_and_broad() {
        assert_eq!(choose(Technique::Auto, 0.9, 0.01).method, Method::Omnee);
        assert_eq!(choose(Technique::Auto, 0.0, 1.0).method, Method::Omnee);
        let thin = choose(Technique::Auto, 0.0, 0.01);
        assert_eq!(thin.method, Method::Mis);
        assert!(thin.reason.unwrap().contains("optically thin"));
        assert!(choose(Technique::Mis, 0.0, 0.01).reason.is_none());
    }
}
