//! The once-more techniques a front end chooses between by name
//! ([`Choice`]: the [`Method`]s of a point-to-point connection, the
//! [`LobeMethod`]s for a lobe at `x0`, and `auto`, [`auto`]), the
//! [`Setup`] that makes one [`Draw`] with any [`Method`], and how a
//! renderer's `multiple` term is estimated ([`MultipleMethod`]).
//!
//! A renderer's once-more term needs, besides the connection `x0 → x2`
//! (which changes with every light sample), the phase function at `x1`, how
//! rays leave the receiver, where the medium is and its extinction σt: the
//! [`Setup`], validated once. Each estimate is then one draw,
//!
//! ```
//! use omnee_core::medium::Region;
//! use omnee_core::method::{Method, Setup};
//! use omnee_core::phase::HenyeyGreenstein;
//! use omnee_core::rng::SplitMix64;
//! use omnee_core::sampling::{Connection, Directions};
//! use glam::Vec3;
//!
//! # fn main() -> Result<(), omnee_core::Error> {
//! let phase = HenyeyGreenstein::new(0.9)?;
//! let setup = Setup::new(phase, Directions::Sphere, Region::Everywhere, 0.55)?;
//! let method: Method = "mis".parse()?;
//! let connection = Connection::new(Vec3::new(0.0, 0.0, 1.0), Vec3::ZERO, core::f32::consts::PI)?;
//! let mut rng = SplitMix64::new(7);
//! let draw = setup.draw_with(method, connection, &mut rng);
//! // The estimate is the sum of f_c · weight over the draw's vertices.
//! let weights: f32 = draw.sum(|s| s.weight);
//! assert!(draw.vertices[0].is_some() && weights > 0.0);
//! # Ok(())
//! # }
//! ```

use crate::error::{Error, check_closed};
use crate::lobe::{Lobe, LobeMis, Restricted, WithLobe};
use crate::medium::Region;
use crate::mis::OmneeMis;
use crate::names::Named;
use crate::phase::PhaseFunction;
use crate::real::Real;
use crate::sampling::{
    Connection, Directions, Distance, Draw, Equiangular, Omnee, Sample, Technique,
};
use core::fmt;
use core::str::FromStr;

/// A technique for the once-more vertex `x1` of a point-to-point
/// connection: what [`Setup`] draws. Front ends name them through
/// [`Choice`], which adds the lobe combination and `auto`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// OMNEE ([`Omnee`]): θ from the phase function, then the circumcircle
    /// arc; weight `θ / (s sin θ)`, restricted to the connection's θmax.
    Omnee,
    /// Equiangular sampling ([`Equiangular`]): a ray from `x2`, the distance
    /// with density `∝ 1/d1²`; weight `p(θ) / (pdf_ω(ω) c)`.
    Equiangular,
    /// Distance sampling ([`Distance`]): a ray from `x2`, the free-flight
    /// distance with density `∝ σt e^{−σt t}` in the medium; weight
    /// `p(θ) / (d1² pdf_ω(ω) pdf(t))`.
    Distance,
    /// OMNEE's vertex over the whole range θ < θmax and, with probability
    /// c = [`OmneeMis::RATE`] (0.05), an equiangular vertex behind the
    /// backward cone θ ≥ [`OmneeMis::THETA_MIN`] (3π/4):
    /// [`OmneeMis::recommended`], the balance heuristic over the expected
    /// counts 1 and c behind the cone (each vertex's weight
    /// `k / (p_O + c p_C)`), OMNEE alone in front of it.
    Mis,
}

impl Method {
    /// Every method, in the order of [`Method::ALLOWED`].
    pub const ALL: [Method; 4] = [
        Method::Omnee,
        Method::Equiangular,
        Method::Distance,
        Method::Mis,
    ];

    /// The names of [`Method::ALL`], as an error message lists them.
    pub const ALLOWED: &'static str = "omnee, equiangular, distance, mis";

    /// The method's name, its [`Choice`]'s: `omnee`, `equiangular`,
    /// `distance` or `mis`.
    pub const fn name(self) -> &'static str {
        self.choice().name()
    }

    /// The [`Choice`] that names this method.
    pub const fn choice(self) -> Choice {
        match self {
            Method::Omnee => Choice::Omnee,
            Method::Equiangular => Choice::Equiangular,
            Method::Distance => Choice::Distance,
            Method::Mis => Choice::Mis,
        }
    }

    /// The method called `name` (exactly, lower case); an
    /// [`Error::Syntax`] for field `technique` that lists the allowed names
    /// otherwise.
    pub fn from_name(name: &str) -> Result<Self, Error> {
        Choice::from_name(name)
            .and_then(Choice::method)
            .ok_or(Error::Syntax {
                field: "technique",
                reason: "unknown name; allowed: omnee, equiangular, distance, mis",
            })
    }
}

impl FromStr for Method {
    type Err = Error;

    /// [`Method::from_name`].
    fn from_str(name: &str) -> Result<Self, Error> {
        Self::from_name(name)
    }
}

impl fmt::Display for Method {
    /// [`Method::name`].
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A technique for the once-more vertex as a front end names it (the
/// command line's `--technique`, a scene's `render.technique`, the
/// bindings): one of the [`Method`]s, the combination for a lobe at `x0`
/// ([`LobeMethod::LobeMis`]), or `auto`, which picks a method from the
/// medium ([`auto`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Choice {
    /// [`Method::Omnee`] (with a lobe at `x0`: [`LobeMethod::Omnee`]).
    Omnee,
    /// [`Method::Equiangular`].
    Equiangular,
    /// [`Method::Distance`].
    Distance,
    /// [`Method::Mis`] (with a lobe at `x0`: [`LobeMethod::LobeMis`]).
    Mis,
    /// [`LobeMethod::LobeMis`]: OMNEE and the lobe technique, one-sample MIS.
    LobeMis,
    /// The method [`auto`] picks (with a lobe at `x0`: [`LobeMethod::LobeMis`]).
    Auto,
}

impl Named for Choice {
    const ALL: &'static [Self] = &[
        Choice::Omnee,
        Choice::Equiangular,
        Choice::Distance,
        Choice::Mis,
        Choice::LobeMis,
        Choice::Auto,
    ];

    fn name(self) -> &'static str {
        Choice::name(self)
    }

    fn help(self) -> &'static str {
        match self {
            Choice::Omnee => {
                "the deflection from the phase function, then x1 on the circumcircle arc"
            }
            Choice::Equiangular => {
                "a direction from the receiver, then the distance equiangular towards the light"
            }
            Choice::Distance => {
                "a direction from the receiver, then an exponential free-flight distance"
            }
            Choice::Mis => {
                "OMNEE over the whole range, and for 5 % of the connections one more, equiangular, vertex kept behind theta = 3 pi/4 (multi-sample MIS, balance heuristic there)"
            }
            Choice::LobeMis => {
                "with a lobe at x0: OMNEE and the lobe technique (a direction from the lobe, then a distance), one-sample balance MIS"
            }
            Choice::Auto => {
                "OMNEE, or mis in a thin medium with a broad phase function; says what it picked and why"
            }
        }
    }
}

crate::display_by_name!(Choice);

impl From<Method> for Choice {
    fn from(method: Method) -> Self {
        method.choice()
    }
}

impl From<LobeMethod> for Choice {
    fn from(method: LobeMethod) -> Self {
        match method {
            LobeMethod::Omnee => Choice::Omnee,
            LobeMethod::LobeMis => Choice::LobeMis,
        }
    }
}

impl Choice {
    /// The choice's name (its [`Named::name`], usable in constants).
    pub const fn name(self) -> &'static str {
        match self {
            Choice::Omnee => "omnee",
            Choice::Equiangular => "equiangular",
            Choice::Distance => "distance",
            Choice::Mis => "mis",
            Choice::LobeMis => "lobe-mis",
            Choice::Auto => "auto",
        }
    }

    /// The [`Method`] of this name (`None` for `lobe-mis` and `auto`).
    pub fn method(self) -> Option<Method> {
        match self {
            Choice::Omnee => Some(Method::Omnee),
            Choice::Equiangular => Some(Method::Equiangular),
            Choice::Distance => Some(Method::Distance),
            Choice::Mis => Some(Method::Mis),
            Choice::LobeMis | Choice::Auto => None,
        }
    }

    /// The method for a connection without a lobe at `x0`: the named one,
    /// or for `auto` the one [`auto`] picks for mean cosine `g` and optical
    /// thickness `tau`, with its reason; `None` for `lobe-mis`.
    pub fn resolve(self, g: f64, tau: f64) -> Option<(Method, Option<AutoReason>)> {
        match self {
            Choice::Auto => {
                let (method, reason) = auto(g, tau);
                Some((method, Some(reason)))
            }
            named => named.method().map(|m| (m, None)),
        }
    }

    /// The technique with a lobe at `x0`: `omnee` is OMNEE with the lobe in
    /// its weight, `mis`, `lobe-mis` and `auto` the recommended combination
    /// with the lobe technique; `None` for the ray methods (`equiangular`,
    /// `distance`), which have no lobe form.
    pub fn lobe_method(self) -> Option<LobeMethod> {
        match self {
            Choice::Omnee => Some(LobeMethod::Omnee),
            Choice::Mis | Choice::LobeMis | Choice::Auto => Some(LobeMethod::LobeMis),
            Choice::Equiangular | Choice::Distance => None,
        }
    }
}

/// The optical thickness below which [`auto`] adds equiangular sampling
/// behind the backward cone for broad phase functions.
pub const AUTO_THIN: f64 = 0.2;

/// The mean cosine from which [`auto`] calls a phase function
/// forward-peaked.
pub const AUTO_PEAKED: f64 = 0.3;

/// Why [`auto`] picked its method: the quantities it looked at, printed as
/// a sentence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AutoReason {
    /// `g ≥` [`AUTO_PEAKED`]: OMNEE.
    ForwardPeaked {
        /// The mean cosine.
        g: f64,
    },
    /// `τ ≥` [`AUTO_THIN`]: OMNEE.
    Attenuating {
        /// The mean cosine.
        g: f64,
        /// The optical thickness.
        tau: f64,
    },
    /// Thin and broad: [`Method::Mis`].
    ThinAndBroad {
        /// The mean cosine.
        g: f64,
        /// The optical thickness.
        tau: f64,
    },
}

impl fmt::Display for AutoReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            AutoReason::ForwardPeaked { g } => write!(
                f,
                "the phase function is forward-peaked (mean cosine {g:.3} >= {AUTO_PEAKED}): OMNEE draws the \
                 deflection from it, and its weight theta/(s sin theta) stays near 1/s"
            ),
            AutoReason::Attenuating { g, tau } => write!(
                f,
                "the medium attenuates along a typical connection (tau = {tau:.3} >= {AUTO_THIN}): attenuation \
                 bounds OMNEE's weight theta/(s sin theta) for backward deflections (mean cosine {g:.3})"
            ),
            AutoReason::ThinAndBroad { g, tau } => write!(
                f,
                "the medium is optically thin (tau = {tau:.3} < {AUTO_THIN}) and the phase function not \
                 forward-peaked (mean cosine {g:.3}): OMNEE's weight grows like 1/(pi - theta) unchecked, so \
                 equiangular sampling joins it behind theta = 3 pi/4"
            ),
        }
    }
}

/// `auto`: OMNEE over the whole range, unless the medium barely attenuates
/// (`tau = σt · distance` of a typical connection below [`AUTO_THIN`]) and
/// the phase function is not forward-peaked (mean cosine `g` below
/// [`AUTO_PEAKED`]); then [`Method::Mis`]. OMNEE's weight θ/(s sin θ) is
/// bounded by attenuation behind the cone (its variance grows like ln(1/τ)
/// as τ → 0, docs/math.md §3.4) and is near 1/s for a forward peak;
/// equiangular sampling alone is never chosen, its variance is infinite for
/// a point-like `x0` (the weight grows like 1/D as the ray passes `x0`).
pub fn auto(g: f64, tau: f64) -> (Method, AutoReason) {
    if g >= AUTO_PEAKED {
        (Method::Omnee, AutoReason::ForwardPeaked { g })
    } else if tau >= AUTO_THIN {
        (Method::Omnee, AutoReason::Attenuating { g, tau })
    } else {
        (Method::Mis, AutoReason::ThinAndBroad { g, tau })
    }
}

/// How a renderer estimates its `multiple` term
/// ([`Term::Multiple`](crate::term::Term::Multiple): light scattered
/// `k = 2 … K` times between the light and a surface point): the scene
/// file's `render.multiple`, the command line's `--multiple`. Both are
/// unbiased estimators of the same integral (docs/math.md §14.9).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MultipleMethod {
    /// A bridge of `k` vertices from the light point to the surface point
    /// ([`crate::bridge::Bridge`]), `k` drawn per connection or fixed:
    /// the deflections from the phase function at every vertex, the chain
    /// turned and scaled onto the connection.
    Bridge,
    /// Path tracing from the surface point: a cosine-weighted direction,
    /// free-flight distances, deflections from the phase function, and at
    /// every vertex next event estimation towards the light (with a sphere
    /// light, balance-heuristic MIS with the phase-sampled rays that hit it).
    PathTracing,
}

impl Named for MultipleMethod {
    const ALL: &'static [Self] = &[MultipleMethod::Bridge, MultipleMethod::PathTracing];

    fn name(self) -> &'static str {
        match self {
            MultipleMethod::Bridge => "bridge",
            MultipleMethod::PathTracing => "path-tracing",
        }
    }

    fn help(self) -> &'static str {
        match self {
            MultipleMethod::Bridge => {
                "a bridge of k vertices from the light to the surface point: deflections from the phase function, the chain turned and scaled onto the connection"
            }
            MultipleMethod::PathTracing => {
                "path tracing from the surface point with next event estimation at every vertex (MIS with phase-sampled hits of a sphere light)"
            }
        }
    }
}

crate::display_by_name!(MultipleMethod);

/// A technique for `x1` when the light leaving `x0` follows a lobe (a phase
/// function about an incoming direction, docs/math.md §12): what
/// [`LobeMethod::technique`] builds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LobeMethod {
    /// OMNEE alone, the lobe's value at `x1` in its weight ([`WithLobe`]).
    Omnee,
    /// The recommended combination ([`LobeMis::recommended`]): OMNEE and the
    /// lobe technique (a direction from the lobe, then a distance along
    /// it), one-sample balance heuristic.
    LobeMis,
}

impl LobeMethod {
    /// The technique for `connection` with `lobe` at its `x0` and `phase`
    /// at `x1`.
    pub fn technique<F: Real, L: Lobe<F> + Copy, P: Restricted<F> + Copy>(
        self,
        connection: Connection<F>,
        lobe: L,
        phase: P,
    ) -> LobeTechnique<F, L, P> {
        match self {
            LobeMethod::Omnee => LobeTechnique::Omnee(WithLobe::new(
                Omnee::new(connection, phase),
                lobe,
                connection.axis.x0,
            )),
            LobeMethod::LobeMis => {
                LobeTechnique::LobeMis(LobeMis::recommended(connection, lobe, phase))
            }
        }
    }
}

/// The technique of a [`LobeMethod`], dispatching to its own.
#[derive(Clone, Copy, Debug)]
pub enum LobeTechnique<F: Real, L, P> {
    /// [`LobeMethod::Omnee`].
    Omnee(WithLobe<F, Omnee<F, P>, L>),
    /// [`LobeMethod::LobeMis`].
    LobeMis(LobeMis<F, L, P>),
}

impl<F: Real, L: Lobe<F> + Copy, P: Restricted<F> + Copy> LobeTechnique<F, L, P> {
    /// The probability `c` with which a draw takes the lobe technique (0 for
    /// OMNEE with the lobe in its weight).
    pub fn lobe_probability(&self) -> F {
        match self {
            LobeTechnique::Omnee(_) => F::ZERO,
            LobeTechnique::LobeMis(t) => t.probability(),
        }
    }
}

impl<F: Real, L: Lobe<F> + Copy, P: Restricted<F> + Copy> Technique<F> for LobeTechnique<F, L, P> {
    fn sample(&self, u: [F; 3]) -> Option<Sample<F>> {
        match self {
            LobeTechnique::Omnee(t) => t.sample(u),
            LobeTechnique::LobeMis(t) => t.sample(u),
        }
    }

    fn pdf(&self, x1: F::Vec3) -> F {
        match self {
            LobeTechnique::Omnee(t) => t.pdf(x1),
            LobeTechnique::LobeMis(t) => t.pdf(x1),
        }
    }

    fn invert(&self, x1: F::Vec3) -> Option<[F; 3]> {
        match self {
            LobeTechnique::Omnee(t) => t.invert(x1),
            LobeTechnique::LobeMis(t) => t.invert(x1),
        }
    }
}

/// Everything a [`Method`] needs besides the connection: the phase function
/// at `x1`, how rays leave the receiver `x2` (equiangular, distance and the
/// MIS companion), where the medium is, and its extinction σt (the
/// free-flight coefficient of distance sampling).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setup<F: Real, P> {
    phase: P,
    directions: Directions<F>,
    region: Region<F>,
    sigma_t: F,
}

impl<F: Real, P: PhaseFunction<F>> Setup<F, P> {
    /// The setup for `phase` at `x1`, rays from `x2` by `directions`
    /// through the medium in `region` with extinction `sigma_t` ∈ [0, ∞)
    /// (an [`Error::OutOfRange`] for field `sigma_t` otherwise, NaN
    /// included). σt = 0 makes distance sampling uniform on bounded
    /// segments and gives it no vertex on unbounded ones.
    pub fn new(
        phase: P,
        directions: Directions<F>,
        region: Region<F>,
        sigma_t: F,
    ) -> Result<Self, Error> {
        check_closed("sigma_t", sigma_t.to_f64(), 0.0, f64::MAX, "[0, inf)")?;
        Ok(Self {
            phase,
            directions,
            region,
            sigma_t,
        })
    }

    /// The same setup with rays from `x2` drawn by `directions` (a renderer
    /// sets the receiver's cosine-weighted directions per shading point; σt
    /// stays checked).
    pub fn with_directions(&self, directions: Directions<F>) -> Self
    where
        P: Clone,
    {
        Self {
            phase: self.phase.clone(),
            directions,
            region: self.region,
            sigma_t: self.sigma_t,
        }
    }

    /// The phase function at `x1`.
    pub fn phase(&self) -> &P {
        &self.phase
    }

    /// How rays leave the receiver.
    pub fn directions(&self) -> Directions<F> {
        self.directions
    }

    /// Where the medium is.
    pub fn region(&self) -> Region<F> {
        self.region
    }

    /// The extinction σt.
    pub fn sigma_t(&self) -> F {
        self.sigma_t
    }

    /// One draw of `method` for `connection` (whose θmax is the
    /// integrand's), the uniform numbers in `[0, 1)` pulled from `next` as
    /// the method needs them: three, or six for [`Method::Mis`] (OMNEE's,
    /// then the companion's). The estimate is [`Draw::sum`] of
    /// `f_c · weight` over its vertices.
    pub fn draw(
        &self,
        method: Method,
        connection: Connection<F>,
        next: impl FnMut() -> F,
    ) -> Draw<F> {
        match method {
            Method::Omnee => Draw::single(&self.omnee(connection), next),
            Method::Equiangular => Draw::single(&self.equiangular(connection), next),
            Method::Distance => Draw::single(&self.distance(connection), next),
            Method::Mis => {
                let companion = self.equiangular(connection);
                OmneeMis::recommended(self.omnee(connection), &companion).draw(next)
            }
        }
    }

    /// [`Setup::draw`] with the numbers from a `rand_core` generator
    /// ([`crate::sampling::uniform`]).
    pub fn draw_with<R: rand_core::Rng + ?Sized>(
        &self,
        method: Method,
        connection: Connection<F>,
        rng: &mut R,
    ) -> Draw<F> {
        self.draw(method, connection, || crate::sampling::uniform(rng))
    }

    /// The volume density the vertices of `method` come with at `x1`: the
    /// technique's [`Technique::pdf`], for [`Method::Mis`] the combined
    /// density [`OmneeMis::pdf`] (`p_O + c p_C` behind the cone, `p_O` in
    /// front of it).
    pub fn pdf(&self, method: Method, connection: Connection<F>, x1: F::Vec3) -> F {
        match method {
            Method::Omnee => self.omnee(connection).pdf(x1),
            Method::Equiangular => self.equiangular(connection).pdf(x1),
            Method::Distance => self.distance(connection).pdf(x1),
            Method::Mis => {
                let companion = self.equiangular(connection);
                OmneeMis::recommended(self.omnee(connection), &companion).pdf(x1)
            }
        }
    }

    #[inline]
    fn omnee(&self, connection: Connection<F>) -> Omnee<F, &P> {
        Omnee::new(connection, &self.phase)
    }

    #[inline]
    fn equiangular(&self, connection: Connection<F>) -> Equiangular<F, &P> {
        Equiangular::new(connection, &self.phase, self.directions, self.region)
    }

    /// Distance sampling with σ = σt, checked by [`Setup::new`].
    #[inline]
    fn distance(&self, connection: Connection<F>) -> Distance<F, &P> {
        Distance::with_checked_sigma(
            connection,
            &self.phase,
            self.directions,
            self.region,
            self.sigma_t,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::phase::HenyeyGreenstein;
    use crate::rng::SplitMix64;
    use crate::sampling::{Sample, uniform};
    use glam::DVec3;

    #[test]
    fn names_round_trip_and_an_unknown_name_lists_the_allowed_ones() {
        let names: std::vec::Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
        assert_eq!(names.join(", "), Method::ALLOWED);
        for m in Method::ALL {
            assert_eq!(Method::from_name(m.name()), Ok(m));
            assert_eq!(m.name().parse::<Method>(), Ok(m));
            assert_eq!(std::format!("{m}"), m.name());
        }
        for bad in ["", "OMNEE", "auto", "omnee ", "equi"] {
            let e = Method::from_name(bad).unwrap_err();
            assert_eq!(e.field(), "technique");
            let message = std::format!("{e}");
            assert!(
                message.ends_with(&std::format!("allowed: {}", Method::ALLOWED)),
                "{bad:?}: {message}"
            );
        }
    }

    #[test]
    fn choices_name_every_method_once_and_resolve_to_them() {
        assert_eq!(
            std::format!("{}", Choice::allowed()),
            "omnee, equiangular, distance, mis, lobe-mis, auto"
        );
        for m in Method::ALL {
            assert_eq!(Choice::from(m).method(), Some(m));
            assert_eq!(Choice::from(m).resolve(0.0, 0.0), Some((m, None)));
        }
        assert_eq!(Choice::LobeMis.resolve(0.9, 1.0), None);
        assert_eq!(Choice::Auto.lobe_method(), Some(LobeMethod::LobeMis));
        assert_eq!(Choice::Omnee.lobe_method(), Some(LobeMethod::Omnee));
        assert_eq!(Choice::Distance.lobe_method(), None);
        for m in [LobeMethod::Omnee, LobeMethod::LobeMis] {
            assert_eq!(Choice::from(m).lobe_method(), Some(m));
        }
    }

    #[test]
    fn auto_picks_omnee_unless_thin_and_broad() {
        let pick = |g, tau| Choice::Auto.resolve(g, tau).unwrap();
        assert_eq!(pick(0.9, 0.01).0, Method::Omnee);
        assert_eq!(pick(0.0, 1.0).0, Method::Omnee);
        let (method, reason) = pick(0.0, 0.01);
        assert_eq!(method, Method::Mis);
        let text = std::format!("{}", reason.unwrap());
        assert!(
            text.contains("optically thin (tau = 0.010 < 0.2)"),
            "{text}"
        );
        assert!(
            std::format!("{}", pick(0.9, 0.01).1.unwrap()).contains("mean cosine 0.900 >= 0.3")
        );
    }

    #[test]
    fn an_invalid_sigma_t_is_an_error_at_construction() {
        let setup = |sigma_t: f64| {
            Setup::new(
                HenyeyGreenstein::new(0.5).unwrap(),
                Directions::Sphere,
                Region::Everywhere,
                sigma_t,
            )
        };
        for bad in [-1e-300, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let e = setup(bad).unwrap_err();
            assert_eq!(e.field(), "sigma_t", "{bad}");
        }
        for good in [0.0, 1e-300, 0.55, 1e300] {
            assert_eq!(setup(good).unwrap().sigma_t(), good);
        }
        let cosine = Directions::cosine(DVec3::Z).unwrap();
        let turned = setup(0.55).unwrap().with_directions(cosine);
        assert_eq!(turned.directions(), cosine);
        assert_eq!(
            (turned.sigma_t(), turned.region()),
            (0.55, Region::Everywhere)
        );
        assert_eq!(turned.phase(), setup(0.55).unwrap().phase());
    }

    /// The setup of the tests: HG 0.7 in a slab, cosine directions about a
    /// tilted normal (equiangular and distance sampling then miss now and
    /// then), and a connection with θmax = π.
    fn setup() -> (Setup<f64, HenyeyGreenstein<f64>>, Connection<f64>) {
        let s = Setup::new(
            HenyeyGreenstein::new(0.7).unwrap(),
            Directions::cosine(DVec3::new(0.3, -0.2, 1.0)).unwrap(),
            Region::slab(-0.5, 2.0).unwrap(),
            1.3,
        )
        .unwrap();
        let c = Connection::new(
            DVec3::new(0.2, -0.1, 1.3),
            DVec3::new(0.5, 0.3, 0.4),
            core::f64::consts::PI,
        )
        .unwrap();
        (s, c)
    }

    /// The vertices of `method`'s technique for the numbers `u`, sampled
    /// directly.
    fn direct(
        s: &Setup<f64, HenyeyGreenstein<f64>>,
        method: Method,
        c: Connection<f64>,
        u: [f64; 6],
    ) -> [Option<Sample<f64>>; 2] {
        let (p, d, r) = (*s.phase(), s.directions(), s.region());
        let first = [u[0], u[1], u[2]];
        let equiangular = Equiangular::new(c, p, d, r);
        match method {
            Method::Omnee => [Omnee::new(c, p).sample(first), None],
            Method::Equiangular => [equiangular.sample(first), None],
            Method::Distance => [
                Distance::new(c, p, d, r, s.sigma_t())
                    .unwrap()
                    .sample(first),
                None,
            ],
            Method::Mis => OmneeMis::recommended(Omnee::new(c, p), &equiangular).sample(u),
        }
    }

    #[test]
    fn a_draw_is_its_techniques_sample_of_the_numbers_it_took() {
        let (setup, c) = setup();
        for method in Method::ALL {
            let mut rng = SplitMix64::new(0x5eed + method as u64);
            let (mut vertices, mut companions) = (0, 0);
            for _ in 0..4000 {
                let mut pulled = std::vec::Vec::new();
                let mut replay = rng.clone();
                let draw = setup.draw(method, c, || {
                    let x = uniform(&mut rng);
                    pulled.push(x);
                    x
                });
                // OmneeMis takes the companion's last two numbers only when
                // its decision number u[3] < c draws it.
                let want = match method {
                    Method::Mis if draw.u[3] < OmneeMis::<f64, HenyeyGreenstein<f64>>::RATE => 6,
                    Method::Mis => 4,
                    _ => 3,
                };
                assert_eq!(draw.taken, want, "{method}");
                assert_eq!(draw.numbers(), &pulled[..], "{method}");
                assert!(draw.u[draw.taken..].iter().all(|&x| x == 0.0));
                assert_eq!(draw.vertices, direct(&setup, method, c, draw.u), "{method}");
                // The generator convenience draws the same numbers.
                assert_eq!(setup.draw_with(method, c, &mut replay), draw, "{method}");
                assert_eq!(replay, rng);
                for (k, s) in draw.vertices.iter().enumerate() {
                    let Some(s) = s else { continue };
                    vertices += 1;
                    companions += k;
                    let (d, _, _) = c.deflection(s.x1).unwrap();
                    let edge = d.one_minus_cos / (1.0 + core::f64::consts::FRAC_1_SQRT_2) - 1.0;
                    if method == Method::Mis && edge.abs() < 1e-9 {
                        continue; // on the cone's edge, classified either way
                    }
                    let pdf = setup.pdf(method, c, s.x1);
                    assert!((pdf / s.pdf - 1.0).abs() < 1e-9, "{method}: {pdf} vs {s:?}");
                }
            }
            assert!(vertices > 1000, "{method}: {vertices} vertices");
            assert_eq!(companions > 0, method == Method::Mis, "{method}");
        }
    }
}
