//! The water surface's optics: refraction on the true normal and the exact
//! Fresnel transmittance of a smooth dielectric for unpolarised light
//! (docs/math.md §13).

use glam::Vec3;

/// Refracts the unit propagation direction `d` at a surface with unit normal
/// `n` (pointing back against `d`, `d · n < 0`) from a medium of index `n1`
/// into one of index `n2`, with `η = n1/n2` and `cos θi = −d·n`:
///
/// `cos²θt = 1 − η² (1 − cos²θi)`, `t = η d + (η cos θi − cos θt) n`
///
/// (Snell's law in vector form, as in pbrt-v4's `Refract`). Returns
/// `(t, cos θt)`, or `None` under total internal reflection or when `d`
/// does not meet the surface from the side `n` points to.
#[inline]
pub fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<(Vec3, f32)> {
    let cos_i = -d.dot(n);
    if !(cos_i > 0.0) {
        return None;
    }
    // 1 − cos²θi as sin²θi of the pair (d, n), kept ≥ 0.
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let cos2_t = 1.0 - eta * eta * sin2_i;
    if !(cos2_t > 0.0) {
        return None;
    }
    let cos_t = cos2_t.sqrt();
    Some(((d * eta + n * (eta * cos_i - cos_t)).normalize(), cos_t))
}

/// The Fresnel reflectance of a smooth dielectric interface for
/// unpolarised light, exact (Born & Wolf §1.5.2):
///
/// `r_s = (n1 cos θi − n2 cos θt) / (n1 cos θi + n2 cos θt)`,
/// `r_p = (n2 cos θi − n1 cos θt) / (n2 cos θi + n1 cos θt)`,
/// `R = (r_s² + r_p²) / 2`,
///
/// with `cos θt` from Snell's law; 1 under total internal reflection.
#[inline]
pub fn fresnel_reflectance(cos_i: f32, n1: f32, n2: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let eta = n1 / n2;
    let cos2_t = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if !(cos2_t > 0.0) {
        return 1.0;
    }
    let cos_t = cos2_t.sqrt();
    let rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
    let rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// The transmittance `T = 1 − R` of [`fresnel_reflectance`]: the fraction
/// of the incident power that enters the water.
#[inline]
pub fn fresnel_transmittance(cos_i: f32, n1: f32, n2: f32) -> f32 {
    1.0 - fresnel_reflectance(cos_i, n1, n2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_reflects_the_textbook_two_percent() {
        // R(0) = ((n − 1)/(n + 1))² = (0.33/2.33)² = 0.020059.
        let r = fresnel_reflectance(1.0, 1.0, 1.33);
        assert!((r - 0.020_059).abs() < 1e-5, "{r}");
    }

    #[test]
    fn brewster_angle_has_no_p_reflection_and_grazing_reflects_all() {
        // At tan θB = n2/n1, r_p = 0: R = r_s²/2 with r_s = cos 2θB... use
        // the closed form r_s = (n1² − n2²)/(n1² + n2²) there.
        let n = 1.33f32;
        let theta_b = n.atan();
        let rs = (1.0 - n * n) / (1.0 + n * n);
        let r = fresnel_reflectance(theta_b.cos(), 1.0, n);
        assert!((r - 0.5 * rs * rs).abs() < 1e-6, "{r}");
        assert!((fresnel_reflectance(0.0, 1.0, n) - 1.0).abs() < 1e-6);
        // Under water beyond the critical angle asin(1/1.33) = 48.75°: total.
        let beyond = (50.0f32).to_radians().cos();
        assert_eq!(fresnel_reflectance(beyond, n, 1.0), 1.0);
        // Reciprocity: T is the same both ways for conjugate angles.
        let ci = (30.0f32).to_radians().cos();
        let (_, ct) = refract(
            Vec3::new(-(1.0 - ci * ci).sqrt(), 0.0, -ci),
            Vec3::Z,
            1.0 / n,
        )
        .unwrap();
        let (a, b) = (
            fresnel_transmittance(ci, 1.0, n),
            fresnel_transmittance(ct, n, 1.0),
        );
        assert!((a - b).abs() < 1e-6, "{a} vs {b}");
    }

    #[test]
    fn refraction_obeys_snell_and_stays_in_the_plane_of_incidence() {
        let n = Vec3::new(0.1, -0.2, 1.0).normalize();
        let d = Vec3::new(0.5, 0.3, -0.8).normalize();
        let (t, cos_t) = refract(d, n, 1.0 / 1.33).unwrap();
        let sin_i = d.cross(n).length();
        let sin_t = t.cross(n).length();
        assert!((sin_i - 1.33 * sin_t).abs() < 1e-6, "{sin_i} {sin_t}");
        assert!((t.length() - 1.0).abs() < 1e-6);
        assert!((-t.dot(n) - cos_t).abs() < 1e-6);
        // Coplanar: t lies in the plane spanned by d and n.
        assert!(t.dot(d.cross(n)).abs() < 1e-6);
        assert!(refract(-d, n, 1.0 / 1.33).is_none(), "from the wrong side");
    }
}
