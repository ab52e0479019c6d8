//! The defensive part of the start density: uniform on a rectangle `R` of
//! the floor, with a heavy tail that covers the whole plane (docs/math.md
//! §13.4):
//!
//! `q(x) = f(u(x)) / Z`, `f(u) = (ℓ/(ℓ + u))³`, `u(x) = dist(x, R)`,
//! `Z = |R| + P ℓ/2 + π ℓ²`
//!
//! (`P` the rectangle's perimeter). `Z` is Steiner's formula: the points at
//! distance `u` from a convex set form a curve of length `P + 2πu`, so
//! `∫ f(u(x)) dA = |R| + ∫₀^∞ f(u) (P + 2πu) du` with `∫ f = ℓ/2` and
//! `∫ f u du = ℓ²/2`. The plane outside `R` is four strips beside the edges,
//! where `u` is the distance across the strip, and four quadrants at the
//! corners, where `u` is the distance to the corner; each is sampled by
//! inverting its 1-D distribution of `u`.

use glam::Vec2;
use std::f32::consts::{FRAC_PI_2, PI};

/// Uniform on the rectangle `[lo, hi]`, `(ℓ/(ℓ + u))³` at the distance `u`
/// outside it, normalised over the plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TailedRect {
    /// Lower corner.
    pub lo: Vec2,
    /// Upper corner.
    pub hi: Vec2,
    /// The tail's length ℓ (m): the density has fallen to 1/8 of the
    /// rectangle's at the distance ℓ from it.
    pub ell: f32,
}

/// The pieces of the plane in the order their masses are laid out on the
/// piece's uniform number: the rectangle, the strips below, above, left
/// and right of it, then the four corner quadrants.
const PIECES: usize = 9;

impl TailedRect {
    /// The rectangle `[lo, hi]` (`lo ≤ hi`) with the tail length `ell > 0`.
    pub fn new(lo: Vec2, hi: Vec2, ell: f32) -> Self {
        Self { lo, hi, ell }
    }

    /// The rectangle's area `|R|`.
    pub fn area(&self) -> f32 {
        let e = self.hi - self.lo;
        e.x * e.y
    }

    /// Whether `p` is in the rectangle.
    pub fn contains(&self, p: Vec2) -> bool {
        p.x >= self.lo.x && p.y >= self.lo.y && p.x <= self.hi.x && p.y <= self.hi.y
    }

    /// The masses of the pieces, unnormalised: `|R|`, `a ℓ/2` for the strips
    /// along the edges of length `a` and `π ℓ²/4` per corner.
    fn masses(&self) -> [f32; PIECES] {
        let e = self.hi - self.lo;
        let (sx, sy) = (0.5 * self.ell * e.x, 0.5 * self.ell * e.y);
        let corner = 0.25 * PI * self.ell * self.ell;
        [e.x * e.y, sx, sx, sy, sy, corner, corner, corner, corner]
    }

    /// The normalisation `Z = |R| + P ℓ/2 + π ℓ²`.
    pub fn normalisation(&self) -> f32 {
        self.masses().iter().sum()
    }

    /// `f(u) = (ℓ/(ℓ + u))³`.
    #[inline]
    fn falloff(&self, u: f32) -> f32 {
        let r = self.ell / (self.ell + u);
        r * r * r
    }

    /// The distance from `p` to the rectangle.
    #[inline]
    pub fn distance(&self, p: Vec2) -> f32 {
        (self.lo - p).max(p - self.hi).max(Vec2::ZERO).length()
    }

    /// The density `q(p) = f(u(p)) / Z` (per unit area).
    pub fn pdf(&self, p: Vec2) -> f32 {
        self.falloff(self.distance(p)) / self.normalisation()
    }

    /// A point with density [`Self::pdf`]: `u[0]` picks the piece by its
    /// mass, `u[1]` and `u[2]` place the point in it. In a strip, `u[1]`
    /// runs along the edge and the distance across it is
    /// `u = ℓ (1/√(1 − u[2]) − 1)` (the inverse of `1 − (ℓ/(ℓ + u))²`, the
    /// cumulative of `f` over `ℓ/2`); in a corner quadrant the angle is
    /// `π/2 · u[1]` and the distance `u = ℓ √u[2] / (1 − √u[2])` (the
    /// inverse of `(u/(ℓ + u))²`, the cumulative of `f(u) u` over `ℓ²/2`).
    pub fn sample(&self, u: [f32; 3]) -> Vec2 {
        let masses = self.masses();
        let total: f32 = masses.iter().sum();
        let mut target = u[0].clamp(0.0, 1.0) * total;
        let mut piece = PIECES - 1;
        for (k, m) in masses.iter().enumerate() {
            if target < *m {
                piece = k;
                break;
            }
            target -= m;
        }
        let (lo, hi, ell) = (self.lo, self.hi, self.ell);
        let e = hi - lo;
        let across = || ell * (1.0 / (1.0 - u[2]).sqrt() - 1.0);
        match piece {
            0 => lo + e * Vec2::new(u[1], u[2]),
            1 => Vec2::new(lo.x + u[1] * e.x, lo.y - across()),
            2 => Vec2::new(lo.x + u[1] * e.x, hi.y + across()),
            3 => Vec2::new(lo.x - across(), lo.y + u[1] * e.y),
            4 => Vec2::new(hi.x + across(), lo.y + u[1] * e.y),
            k => {
                // `1 − √v = (1 − v)/(1 + √v)`, without cancellation.
                let s = u[2].sqrt();
                let dist = ell * s * (1.0 + s) / (1.0 - u[2]);
                let (sin, cos) = (FRAC_PI_2 * u[1]).sin_cos();
                // Corners (lo.x, lo.y), (hi.x, lo.y), (lo.x, hi.y), (hi.x, hi.y),
                // each with its quadrant pointing away from the rectangle.
                let (right, up) = ((k - 5) % 2 == 1, k >= 7);
                let corner = Vec2::new(
                    if right { hi.x } else { lo.x },
                    if up { hi.y } else { lo.y },
                );
                let sign = Vec2::new(if right { 1.0 } else { -1.0 }, if up { 1.0 } else { -1.0 });
                corner + sign * Vec2::new(cos, sin) * dist
            }
        }
    }

    /// The numbers `u` with `sample(u) = p` (the piece's number at the middle
    /// of its interval).
    pub fn invert(&self, p: Vec2) -> [f32; 3] {
        let (lo, hi, ell) = (self.lo, self.hi, self.ell);
        let e = hi - lo;
        let (left, right) = (p.x < lo.x, p.x > hi.x);
        let (below, above) = (p.y < lo.y, p.y > hi.y);
        // The inverse of `u = ℓ (1/√(1 − v) − 1)`: `v = 1 − (ℓ/(ℓ + u))²`.
        let strip = |u: f32| 1.0 - (ell / (ell + u)).powi(2);
        let along = |x: f32, a: f32, len: f32| if len > 0.0 { (x - a) / len } else { 0.5 };
        let (piece, u1, u2) = match (left || right, below || above) {
            (false, false) => (0, along(p.x, lo.x, e.x), along(p.y, lo.y, e.y)),
            (false, true) => {
                let u = if below { lo.y - p.y } else { p.y - hi.y };
                (if below { 1 } else { 2 }, along(p.x, lo.x, e.x), strip(u))
            }
            (true, false) => {
                let u = if left { lo.x - p.x } else { p.x - hi.x };
                (if left { 3 } else { 4 }, along(p.y, lo.y, e.y), strip(u))
            }
            (true, true) => {
                let corner = Vec2::new(
                    if right { hi.x } else { lo.x },
                    if above { hi.y } else { lo.y },
                );
                let d = (p - corner).abs();
                let dist = d.length();
                let s = dist / (ell + dist);
                let k = 5 + usize::from(right) + 2 * usize::from(above);
                (k, d.y.atan2(d.x) / FRAC_PI_2, s * s)
            }
        };
        let masses = self.masses();
        let total: f32 = masses.iter().sum();
        let before: f32 = masses[..piece].iter().sum();
        [(before + 0.5 * masses[piece]) / total, u1, u2]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect() -> TailedRect {
        TailedRect::new(Vec2::new(-1.0, 2.0), Vec2::new(3.0, 3.5), 0.8)
    }

    #[test]
    fn the_density_integrates_to_one_over_the_plane() {
        // Midpoint rule on a 400 m square (the mass beyond it, in the tail
        // ∝ 1/u², is ~ (P ℓ²/(2 · 200) + π ℓ³ · 2/200)/Z ≈ 5e-4) in f64
        // from the f32 density.
        let r = rect();
        let (half, n) = (200.0f64, 4000);
        let h = 2.0 * half / n as f64;
        let mut sum = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let p = Vec2::new(
                    (-half + (i as f64 + 0.5) * h) as f32,
                    (-half + (j as f64 + 0.5) * h) as f32,
                );
                sum += r.pdf(p) as f64 * h * h;
            }
        }
        // The tail beyond the square: Σ over strips and corners of
        // ∫_{U}^∞ f(u)(P + 2πu) du with U ≈ 198 m.
        let (ell, u) = (0.8f64, 198.0f64);
        let z = r.normalisation() as f64;
        let beyond = (11.0 * ell.powi(3) / (2.0 * (ell + u).powi(2))
            + 2.0 * std::f64::consts::PI * ell.powi(3) / (ell + u))
            / z;
        assert!((sum + beyond - 1.0).abs() < 2e-3, "{sum} + {beyond}");
    }

    /// The piece of the plane `p` lies in (the order of [`PIECES`]).
    fn piece(r: &TailedRect, p: Vec2) -> usize {
        let (left, right) = (p.x < r.lo.x, p.x > r.hi.x);
        let (below, above) = (p.y < r.lo.y, p.y > r.hi.y);
        match (left || right, below || above) {
            (false, false) => 0,
            (false, true) => 1 + usize::from(above),
            (true, false) => 3 + usize::from(right),
            (true, true) => 5 + usize::from(right) + 2 * usize::from(above),
        }
    }

    #[test]
    fn samples_follow_the_density_and_invert() {
        // Pearson's χ² over 33 cells: the rectangle, and each of the eight
        // outer pieces in four rings of the distance u, against the masses
        // `a ℓ/2 (1 − (ℓ/(ℓ + u))²)` (strip along an edge of length a) and
        // `π ℓ²/4 (u/(ℓ + u))²` (corner) between the rings' edges; 32
        // degrees of freedom, rejected above 70.57 (p = 1e-4). Every sample
        // inverts to its numbers.
        let r = rect();
        let z = r.normalisation() as f64;
        let ell = r.ell as f64;
        let e = (r.hi - r.lo).as_dvec2();
        let edges = [0.0f64, 0.3, 1.0, 4.0, f64::INFINITY];
        let mass = |piece: usize, u: f64| {
            if u.is_infinite() {
                return match piece {
                    1 | 2 => e.x * ell / 2.0,
                    3 | 4 => e.y * ell / 2.0,
                    _ => std::f64::consts::FRAC_PI_4 * ell * ell,
                };
            }
            let a = ell / (ell + u);
            match piece {
                1 | 2 => e.x * ell / 2.0 * (1.0 - a * a),
                3 | 4 => e.y * ell / 2.0 * (1.0 - a * a),
                _ => std::f64::consts::FRAC_PI_4 * ell * ell * (u / (ell + u)).powi(2),
            }
        };
        let mut expected = vec![r.area() as f64 / z];
        for piece in 1..PIECES {
            for w in edges.windows(2) {
                expected.push((mass(piece, w[1]) - mass(piece, w[0])) / z);
            }
        }
        let mut counts = vec![0u64; expected.len()];
        let n = 1_000_000u64;
        let mut rng = crate::rng::Rng::stream(3, 1, 4);
        for _ in 0..n {
            let u = [rng.uniform(), rng.uniform(), rng.uniform()];
            let p = r.sample(u);
            let v = r.invert(p);
            // f32 keeps `1 − u[2]` to 2ε/(1 − u[2]) relative, far out in a tail.
            let tolerance = 1e-4 + 2.4e-7 / (1.0 - u[2]);
            assert!(
                (r.sample(v) - p).length() < tolerance * (1.0 + p.length()),
                "{u:?}"
            );
            assert!((v[1] - u[1]).abs() < 1e-3 && (v[2] - u[2]).abs() < 1e-3);
            let k = piece(&r, p);
            let cell = if k == 0 {
                0
            } else {
                let d = r.distance(p) as f64;
                1 + 4 * (k - 1)
                    + edges
                        .windows(2)
                        .position(|w| d >= w[0] && d < w[1])
                        .unwrap()
            };
            counts[cell] += 1;
        }
        let chi2: f64 = counts
            .iter()
            .zip(&expected)
            .map(|(&c, &q)| {
                let want = q * n as f64;
                (c as f64 - want).powi(2) / want
            })
            .sum();
        assert!((expected.iter().sum::<f64>() - 1.0).abs() < 1e-5);
        assert!(chi2 < 70.57, "chi2 {chi2}: {counts:?}");
    }
}
