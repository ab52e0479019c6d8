//! The water surface: flat, or a sum of directional sine or Gerstner waves,
//! as a height field `z = h(x, y)` with its true normal, and robust ray
//! intersection by Lipschitz-bounded marching (docs/math.md §13).

use glam::{Vec2, Vec3};

/// The shape of every wave of a surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WaveKind {
    /// `h = z + Σ a sin(k d·p + φ)`: a plain height field; never folds.
    Sine,
    /// Gerstner (trochoidal) waves: the surface point of the rest position
    /// `q` is `(q − Σ a d sin(k d·q + φ), z + Σ a cos(k d·q + φ))`, sharp
    /// crests and flat troughs; folds unless `Σ a k < 1`.
    Gerstner,
}

/// One directional wave.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wave {
    /// Amplitude `a` (m).
    pub amplitude: f32,
    /// Wavenumber `k = 2π / wavelength` (1/m).
    pub k: f32,
    /// Unit direction of travel `d` in the xy plane.
    pub direction: Vec2,
    /// Phase `φ` (rad).
    pub phase: f32,
}

impl Wave {
    /// The wave's phase at the horizontal point `q`: `k d·q + φ`.
    #[inline]
    fn angle(&self, q: Vec2) -> f32 {
        self.k * self.direction.dot(q) + self.phase
    }
}

/// The sums of a Gerstner surface at a rest position `q`: the horizontal
/// shift `Σ a d sin θ`, the symmetric Jacobian `J = I − Σ a k cos θ d dᵀ` of
/// `q ↦ q − shift` as `[J00, J01, J11]`, the height and `∂h/∂q`.
struct Rest {
    shift: Vec2,
    jacobian: [f32; 3],
    height: f32,
    dh_dq: Vec2,
}

impl Rest {
    /// `J⁻¹ v` (J symmetric, positive definite when `Σ a k < 1`).
    #[inline]
    fn solve(&self, v: Vec2) -> Vec2 {
        let [a, b, c] = self.jacobian;
        let det = a * c - b * b;
        Vec2::new((c * v.x - b * v.y) / det, (a * v.y - b * v.x) / det)
    }
}

/// The largest steepness sum `Σ a k` a Gerstner surface may have: at 1 its
/// crests become cusps and beyond it the surface folds over itself.
pub const GERSTNER_FOLD: f32 = 1.0;

/// A point of the surface: its height and upward unit normal.
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint {
    /// `h(x, y)`.
    pub height: f32,
    /// The true normal `(−∂h/∂x, −∂h/∂y, 1)` normalised.
    pub normal: Vec3,
}

/// The water surface: mean height, waves, and the bounds marching needs.
#[derive(Clone, Debug)]
pub struct Surface {
    /// Mean height `z` (m).
    pub z: f32,
    kind: WaveKind,
    waves: Vec<Wave>,
    /// `Σ a`: the surface lies in `[z − Σ a, z + Σ a]`.
    amplitude_sum: f32,
    /// A bound on `|∇h|`: `Σ a k` for sine waves, `S/(1 − S)` with
    /// `S = Σ a k` for Gerstner waves.
    slope_bound: f32,
}

/// Why a set of waves is not a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FoldError {
    /// The steepness sum `Σ a k`.
    pub steepness: f32,
}

impl Surface {
    /// A flat surface at height `z`.
    pub fn flat(z: f32) -> Self {
        Self {
            z,
            kind: WaveKind::Sine,
            waves: Vec::new(),
            amplitude_sum: 0.0,
            slope_bound: 0.0,
        }
    }

    /// Waves of `kind` about the mean height `z`. Gerstner waves with
    /// `Σ a k ≥ 1` fold: [`FoldError`].
    pub fn new(z: f32, kind: WaveKind, waves: Vec<Wave>) -> Result<Self, FoldError> {
        let steepness: f32 = waves.iter().map(|w| w.amplitude * w.k).sum();
        let slope_bound = match kind {
            WaveKind::Sine => steepness,
            WaveKind::Gerstner => {
                if !(steepness < GERSTNER_FOLD) {
                    return Err(FoldError { steepness });
                }
                steepness / (1.0 - steepness)
            }
        };
        Ok(Self {
            z,
            kind,
            amplitude_sum: waves.iter().map(|w| w.amplitude).sum(),
            waves,
            slope_bound,
        })
    }

    /// Whether there are no waves.
    pub fn is_flat(&self) -> bool {
        self.waves.is_empty()
    }

    /// The lowest the surface gets, `z − Σ a`: below it is water everywhere.
    pub fn trough(&self) -> f32 {
        self.z - self.amplitude_sum
    }

    /// The highest the surface gets, `z + Σ a`.
    pub fn crest(&self) -> f32 {
        self.z + self.amplitude_sum
    }

    /// The height and true normal at the horizontal point `p`.
    ///
    /// Sine: `h = z + Σ a sin θ`, `∇h = Σ a k cos θ d` with `θ = k d·p + φ`.
    /// Gerstner: the rest position `q` with `q − Σ a d sin θ(q) = p` by
    /// Newton's method on that 2-D map (its Jacobian
    /// `J = I − Σ a k cos θ d dᵀ` is invertible when `Σ a k < 1`), then
    /// `h = z + Σ a cos θ(q)` and `∇h = J⁻ᵀ ∂h/∂q`, `∂h/∂q = −Σ a k sin θ d`.
    pub fn at(&self, p: Vec2) -> SurfacePoint {
        let (height, grad) = match self.kind {
            WaveKind::Sine => {
                let mut h = self.z;
                let mut g = Vec2::ZERO;
                for w in &self.waves {
                    let (s, c) = w.angle(p).sin_cos();
                    h += w.amplitude * s;
                    g += w.direction * (w.amplitude * w.k * c);
                }
                (h, g)
            }
            WaveKind::Gerstner => self.gerstner(p),
        };
        SurfacePoint {
            height,
            normal: Vec3::new(-grad.x, -grad.y, 1.0).normalize(),
        }
    }

    /// The height alone (the marching loop's function).
    #[inline]
    pub fn height(&self, p: Vec2) -> f32 {
        match self.kind {
            WaveKind::Sine => {
                self.z
                    + self
                        .waves
                        .iter()
                        .map(|w| w.amplitude * w.angle(p).sin())
                        .sum::<f32>()
            }
            WaveKind::Gerstner => self.gerstner(p).0,
        }
    }

    /// Height and gradient of a Gerstner surface at `p` (see [`Self::at`]).
    fn gerstner(&self, p: Vec2) -> (f32, Vec2) {
        // Fixed-point start q = p + Σ a d sin θ(p), then Newton on
        // r(q) = q − Σ a d sin θ(q) − p.
        let mut q = p + self.rest(p).shift;
        let mut rest = self.rest(q);
        for _ in 0..8 {
            let step = rest.solve(q - rest.shift - p);
            q -= step;
            rest = self.rest(q);
            if step.length_squared() < 1e-14 * (1.0 + q.length_squared()) {
                break;
            }
        }
        // ∇h = J⁻ᵀ ∂h/∂q (J is symmetric).
        (rest.height, rest.solve(rest.dh_dq))
    }

    /// The Gerstner sums at the rest position `q`.
    fn rest(&self, q: Vec2) -> Rest {
        let mut r = Rest {
            shift: Vec2::ZERO,
            jacobian: [1.0, 0.0, 1.0],
            height: self.z,
            dh_dq: Vec2::ZERO,
        };
        for w in &self.waves {
            let (s, c) = w.angle(q).sin_cos();
            let d = w.direction;
            r.shift += d * (w.amplitude * s);
            r.height += w.amplitude * c;
            r.dh_dq -= d * (w.amplitude * w.k * s);
            let f = w.amplitude * w.k * c;
            r.jacobian[0] -= f * d.x * d.x;
            r.jacobian[1] -= f * d.x * d.y;
            r.jacobian[2] -= f * d.y * d.y;
        }
        r
    }

    /// The first point where the ray `o + t d` (unit `d`, going down,
    /// `o` at or above [`Self::crest`]) meets the surface, as `(t, point)`.
    ///
    /// `f(t) = o_z + t d_z − h(o_xy + t d_xy)` is positive above the surface
    /// and changes by at most `L = |d_z| + |∇h|max |d_xy|` per unit `t`, so
    /// the step `t += f/L` never passes the first root (sphere tracing of a
    /// height field, Hart 1996); it stops when `f` is below 10 µm. A flat
    /// surface is hit in closed form.
    pub fn hit_from_above(&self, o: Vec3, d: Vec3) -> Option<(f32, SurfacePoint)> {
        if !(d.z < 0.0) {
            return None;
        }
        if self.is_flat() {
            let t = (self.z - o.z) / d.z;
            return (t >= 0.0).then_some((
                t,
                SurfacePoint {
                    height: self.z,
                    normal: Vec3::Z,
                },
            ));
        }
        let lipschitz = -d.z + self.slope_bound * d.truncate().length();
        // Start where the ray enters the band [trough, crest].
        let mut t = ((self.crest() - o.z) / d.z).max(0.0);
        let t_end = (self.trough() - o.z) / d.z;
        for _ in 0..MARCH_STEPS {
            let p = o + d * t;
            let f = p.z - self.height(p.truncate());
            if f < MARCH_TOLERANCE {
                let point = self.at(p.truncate());
                return Some((t, point));
            }
            t += f / lipschitz;
            if t > t_end {
                // Below the troughs the surface must have been met; rounding
                // left f > 0: the hit is at the trough plane.
                t = t_end;
            }
        }
        let p = o + d * t;
        Some((t, self.at(p.truncate())))
    }

    /// Whether the segment `a → b` (both under water) stays under the
    /// surface: `g = h(xy) − z > 0` along it, marched with steps `g / L` like
    /// [`Self::hit_from_above`] over the part above the troughs (below them
    /// there is nothing to test).
    pub fn segment_under(&self, a: Vec3, b: Vec3) -> bool {
        let trough = self.trough();
        if self.is_flat() || (a.z <= trough && b.z <= trough) {
            return true;
        }
        let delta = b - a;
        // The parameter range with z ≥ trough.
        let (mut t, t_end) = if delta.z == 0.0 {
            (0.0, 1.0)
        } else {
            let tz = (trough - a.z) / delta.z;
            if delta.z > 0.0 {
                (tz.max(0.0), 1.0)
            } else {
                (0.0, tz.min(1.0))
            }
        };
        let lipschitz = delta.z.abs() + self.slope_bound * delta.truncate().length();
        if !(lipschitz > 0.0) {
            return true;
        }
        for _ in 0..MARCH_STEPS {
            let p = a + delta * t;
            let g = self.height(p.truncate()) - p.z;
            if g <= 0.0 {
                return false;
            }
            t += g / lipschitz;
            if t >= t_end {
                return true;
            }
        }
        true
    }
}

/// Marching steps before giving up (the ray then grazes the surface within
/// the last step).
const MARCH_STEPS: usize = 512;
/// The distance above the surface at which a marching ray counts as a hit (m).
const MARCH_TOLERANCE: f32 = 1e-5;

#[cfg(test)]
mod tests {
    use super::*;

    fn waves() -> Vec<Wave> {
        vec![
            Wave {
                amplitude: 0.08,
                k: std::f32::consts::TAU / 3.0,
                direction: Vec2::new(1.0, 0.0),
                phase: 0.3,
            },
            Wave {
                amplitude: 0.04,
                k: std::f32::consts::TAU / 1.3,
                direction: Vec2::new(0.6, 0.8),
                phase: 1.7,
            },
            Wave {
                amplitude: 0.02,
                k: std::f32::consts::TAU / 0.7,
                direction: Vec2::new(-0.28, 0.96),
                phase: 4.0,
            },
        ]
    }

    #[test]
    fn gradients_match_finite_differences_for_both_kinds() {
        for kind in [WaveKind::Sine, WaveKind::Gerstner] {
            let s = Surface::new(0.0, kind, waves()).unwrap();
            for &(x, y) in &[(0.1f32, 0.2f32), (1.3, -0.7), (-2.2, 3.1), (5.0, 5.0)] {
                let p = Vec2::new(x, y);
                let n = s.at(p).normal;
                let e = 1e-3;
                let gx = (s.height(p + Vec2::X * e) - s.height(p - Vec2::X * e)) / (2.0 * e);
                let gy = (s.height(p + Vec2::Y * e) - s.height(p - Vec2::Y * e)) / (2.0 * e);
                let want = Vec3::new(-gx, -gy, 1.0).normalize();
                assert!((n - want).length() < 2e-3, "{kind:?} at {p}: {n} vs {want}");
                assert!(n.z > 0.0);
            }
        }
    }

    #[test]
    fn gerstner_points_invert_their_rest_positions() {
        let s = Surface::new(0.5, WaveKind::Gerstner, waves()).unwrap();
        let ws = waves();
        for &(x, y) in &[(0.0f32, 0.0f32), (0.77, 2.1), (-3.0, 1.0)] {
            // Forward map of a rest position, then the height there.
            let q = Vec2::new(x, y);
            let mut p = q;
            let mut z = 0.5;
            for w in &ws {
                let (sn, c) = w.angle(q).sin_cos();
                p -= w.direction * (w.amplitude * sn);
                z += w.amplitude * c;
            }
            assert!((s.height(p) - z).abs() < 1e-5, "{} vs {z}", s.height(p));
        }
    }

    #[test]
    fn gerstner_waves_that_fold_are_refused_and_sine_waves_never_are() {
        let steep = vec![Wave {
            amplitude: 0.5,
            k: 2.5,
            direction: Vec2::X,
            phase: 0.0,
        }];
        let e = Surface::new(0.0, WaveKind::Gerstner, steep.clone()).unwrap_err();
        assert!((e.steepness - 1.25).abs() < 1e-6);
        assert!(Surface::new(0.0, WaveKind::Sine, steep).is_ok());
    }

    #[test]
    fn marching_finds_the_first_crossing_for_steep_and_grazing_rays() {
        for kind in [WaveKind::Sine, WaveKind::Gerstner] {
            let s = Surface::new(0.0, kind, waves()).unwrap();
            for i in 0..200 {
                let a = i as f32 * 0.1;
                let elevation = 0.15 + 1.4 * (i as f32 / 200.0);
                let d = Vec3::new(
                    elevation.cos() * a.cos(),
                    elevation.cos() * a.sin(),
                    -elevation.sin(),
                );
                let o = Vec3::new(a.sin() * 3.0, a.cos() * 2.0, s.crest() + 0.01);
                let (t, sp) = s.hit_from_above(o, d).unwrap();
                let p = o + d * t;
                assert!(
                    (p.z - sp.height).abs() < 1e-4,
                    "{kind:?} {i}: off the surface"
                );
                // No earlier crossing: a fine scan from the start stays above.
                let n = 4000;
                for j in 0..n {
                    let tj = t * j as f32 / n as f32;
                    let q = o + d * tj;
                    assert!(
                        q.z - s.height(q.truncate()) > -1e-4,
                        "{kind:?} {i}: passed a crossing"
                    );
                }
            }
        }
    }

    #[test]
    fn segments_that_poke_through_a_crest_are_caught() {
        let s = Surface::new(0.0, WaveKind::Sine, waves()).unwrap();
        let below = s.trough() - 0.5;
        assert!(s.segment_under(Vec3::new(0.0, 0.0, below), Vec3::new(3.0, 1.0, below)));
        // A horizontal segment at the mean height must cross the surface.
        assert!(!s.segment_under(Vec3::new(-5.0, 0.0, 0.0), Vec3::new(5.0, 0.3, 0.0)));
        // Up to a point just under the surface: stays under.
        let top = Vec2::new(0.4, 0.2);
        let h = s.height(top);
        assert!(s.segment_under(Vec3::new(0.4, 0.2, below), Vec3::new(0.4, 0.2, h - 1e-3)));
    }
}
