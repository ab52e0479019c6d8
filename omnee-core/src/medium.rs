//! The medium: homogeneous coefficients, closed-form transmittance, and the
//! region of space it fills.

use crate::error::{Error, check_closed};
use crate::real::{Real, Vector};

/// A homogeneous medium with scattering and absorption coefficients (1/m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Homogeneous<F> {
    sigma_s: F,
    sigma_t: F,
}

impl<F: Real> Homogeneous<F> {
    /// A medium with `σs ≥ 0` and `σa ≥ 0` (finite).
    pub fn new(sigma_s: F, sigma_a: F) -> Result<Self, Error> {
        check_closed("sigma_s", sigma_s.to_f64(), 0.0, f64::MAX, "[0, inf)")?;
        check_closed("sigma_a", sigma_a.to_f64(), 0.0, f64::MAX, "[0, inf)")?;
        Self::from_extinction(sigma_s, sigma_s + sigma_a)
    }

    /// A medium given by `σs ≥ 0` and `σt ≥ 0` (finite). Unlike [`Self::new`]
    /// it accepts `σt < σs`: analytic test problems use σt = 0 with σs > 0 to
    /// switch attenuation off (docs/math.md §5).
    pub fn from_extinction(sigma_s: F, sigma_t: F) -> Result<Self, Error> {
        check_closed("sigma_s", sigma_s.to_f64(), 0.0, f64::MAX, "[0, inf)")?;
        check_closed("sigma_t", sigma_t.to_f64(), 0.0, f64::MAX, "[0, inf)")?;
        Ok(Self { sigma_s, sigma_t })
    }

    /// The scattering coefficient σs.
    #[inline]
    pub fn sigma_s(&self) -> F {
        self.sigma_s
    }

    /// The absorption coefficient `σa = σt − σs`.
    #[inline]
    pub fn sigma_a(&self) -> F {
        self.sigma_t - self.sigma_s
    }

    /// The extinction coefficient `σt = σs + σa`.
    #[inline]
    pub fn sigma_t(&self) -> F {
        self.sigma_t
    }

    /// Transmittance over a distance `d`: `T(d) = exp(−σt d)`.
    #[inline]
    pub fn transmittance(&self, d: F) -> F {
        let sigma_t = self.sigma_t();
        // Without extinction T = 1 at any distance (exp(−0 · ∞) would be NaN).
        if sigma_t > F::ZERO {
            (-sigma_t * d).exp()
        } else {
            F::ONE
        }
    }
}

/// The part of space the medium fills. Outside it σs = σt = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Region<F> {
    /// All of space (an infinite medium).
    Everywhere,
    /// The slab `z_min ≤ z ≤ z_max`.
    Slab {
        /// The lower plane.
        z_min: F,
        /// The upper plane.
        z_max: F,
    },
}

impl<F: Real> Region<F> {
    /// The slab `z_min ≤ z ≤ z_max`; both finite and `z_min < z_max`.
    pub fn slab(z_min: F, z_max: F) -> Result<Self, Error> {
        check_closed("z_min", z_min.to_f64(), f64::MIN, f64::MAX, "finite")?;
        check_closed(
            "z_max",
            z_max.to_f64(),
            z_min.to_f64(),
            f64::MAX,
            "(z_min, inf)",
        )?;
        if z_max == z_min {
            return Err(Error::Degenerate {
                field: "z_max",
                reason: "equals z_min (empty slab)",
            });
        }
        Ok(Region::Slab { z_min, z_max })
    }

    /// Whether `p` lies in the region (boundaries included).
    #[inline]
    pub fn contains(&self, p: F::Vec3) -> bool {
        match *self {
            Region::Everywhere => true,
            Region::Slab { z_min, z_max } => p.z() >= z_min && p.z() <= z_max,
        }
    }

    /// The parameter interval `[t_a, t_b]`, `0 ≤ t_a < t_b ≤ ∞`, of the ray
    /// `origin + t·dir` (t ≥ 0) inside the region; `None` if the ray misses it.
    /// For the slab, `t = (z − origin.z)/dir.z` at both planes.
    #[inline]
    pub fn segment(&self, origin: F::Vec3, dir: F::Vec3) -> Option<(F, F)> {
        match *self {
            Region::Everywhere => Some((F::ZERO, F::INFINITY)),
            Region::Slab { z_min, z_max } => {
                let (oz, dz) = (origin.z(), dir.z());
                if dz == F::ZERO {
                    return (oz >= z_min && oz <= z_max).then_some((F::ZERO, F::INFINITY));
                }
                let (t1, t2) = ((z_min - oz) / dz, (z_max - oz) / dz);
                let (lo, hi) = if t1 < t2 { (t1, t2) } else { (t2, t1) };
                let lo = lo.max(F::ZERO);
                (hi > lo).then_some((lo, hi))
            }
        }
    }
}
