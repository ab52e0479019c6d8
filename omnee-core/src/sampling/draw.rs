//! One draw of a once-more technique: up to two vertices `x1` and the
//! uniform numbers they came from.

use super::{Sample, Technique};
use crate::real::Real;

/// One draw: the vertices of one estimate and the uniform numbers taken.
///
/// A single technique's draw takes three numbers and has one vertex (or
/// none); [`crate::mis::OmneeMis::draw`] has OMNEE's vertex and now and then
/// a companion's. The once-more estimate of the draw is the sum over its
/// vertices,
///
/// `⟨I⟩ = Σ_k f_c(x1_k) · weight_k`,
///
/// which is [`Draw::sum`] of `f_c · weight` (e.g.
/// [`PointToPoint::estimate`](crate::reference::PointToPoint::estimate)).
///
/// Numbers are pulled one at a time from a source `next: FnMut() -> F` (a
/// generator, a sampler's dimensions, a slice), as many as the technique
/// needs: a technique that draws more only when it has to (a companion
/// vertex drawn now and then) takes fewer on average, and its callers do
/// not change.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Draw<F: Real> {
    /// The numbers in the order they were taken, `u[0..3]` for the first
    /// vertex and `u[3..6]` for the second's; zero past [`Draw::taken`].
    pub u: [F; 6],
    /// How many of `u` were taken (3 for a single technique; for
    /// [`crate::mis::OmneeMis`] 6 with a companion vertex drawn, else 4).
    pub taken: usize,
    /// The vertices: the technique's own (OMNEE's for
    /// [`crate::mis::OmneeMis`]) and the companion's; `None` where the
    /// numbers give no vertex or no companion was drawn.
    pub vertices: [Option<Sample<F>>; 2],
}

impl<F: Real> Draw<F> {
    /// The most uniform numbers one draw takes.
    pub const MAX_NUMBERS: usize = 6;

    /// The draw of one vertex of `technique` from the next three numbers,
    /// `technique.sample([next(), next(), next()])`.
    #[inline]
    pub fn single<T: Technique<F> + ?Sized>(technique: &T, mut next: impl FnMut() -> F) -> Self {
        let u = [next(), next(), next()];
        Self {
            u: [u[0], u[1], u[2], F::ZERO, F::ZERO, F::ZERO],
            taken: 3,
            vertices: [technique.sample(u), None],
        }
    }

    /// The numbers taken, `&u[..taken]`.
    #[inline]
    pub fn numbers(&self) -> &[F] {
        &self.u[..self.taken]
    }

    /// The three numbers of vertex `k`, `u[3k..3k + 3]`: the technique's
    /// own for `k = 0`, the companion's for `k = 1` (of which
    /// [`crate::mis::OmneeMis`] also uses the first to decide whether to
    /// draw the companion at all); `None` where they were not all taken.
    #[inline]
    pub fn vertex_numbers(&self, k: usize) -> Option<[F; 3]> {
        let start = k.checked_mul(3)?;
        let u = self.numbers().get(start..)?.get(..3)?;
        Some([u[0], u[1], u[2]])
    }

    /// The vertices that were drawn, the technique's own first.
    #[inline]
    pub fn samples(&self) -> impl Iterator<Item = &Sample<F>> {
        self.vertices.iter().flatten()
    }

    /// `Σ_k f(x1_k)` over the vertices drawn (0 for none): with
    /// `f = f_c · weight` the draw's estimate.
    #[inline]
    pub fn sum<T: core::iter::Sum<T>>(&self, f: impl FnMut(&Sample<F>) -> T) -> T {
        self.samples().map(f).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::phase::Isotropic;
    use crate::sampling::{Connection, Omnee};
    use glam::DVec3;

    #[test]
    fn a_single_draw_takes_three_numbers_in_order() {
        let c = Connection::new(DVec3::ZERO, DVec3::Z, core::f64::consts::PI).unwrap();
        let omnee = Omnee::new(c, Isotropic);
        let mut calls = 0;
        let draw = Draw::single(&omnee, || {
            calls += 1;
            0.125 * calls as f64
        });
        assert_eq!(calls, 3);
        assert_eq!(draw.u, [0.125, 0.25, 0.375, 0.0, 0.0, 0.0]);
        assert_eq!((draw.taken, draw.numbers()), (3, &[0.125, 0.25, 0.375][..]));
        assert_eq!(draw.vertex_numbers(0), Some([0.125, 0.25, 0.375]));
        assert_eq!(draw.vertex_numbers(1), None);
        assert_eq!(draw.vertex_numbers(usize::MAX), None);
        assert_eq!(draw.vertices, [omnee.sample([0.125, 0.25, 0.375]), None]);
        assert!(draw.vertices[0].is_some());
    }

    #[test]
    fn the_estimate_sums_over_the_vertices_drawn() {
        let vertex = |weight: f64| Sample {
            x1: DVec3::X,
            pdf: 1.0,
            weight,
        };
        let mut draw = Draw {
            u: [0.5; 6],
            taken: 6,
            vertices: [Some(vertex(2.0)), Some(vertex(0.25))],
        };
        assert_eq!(draw.vertex_numbers(1), Some([0.5; 3]));
        assert_eq!(draw.sum(|s| s.weight), 2.25);
        assert_eq!(draw.samples().count(), 2);
        draw.vertices[0] = None;
        assert_eq!(draw.sum(|s| 4.0 * s.weight), 1.0);
        draw.vertices[1] = None;
        assert_eq!(draw.sum(|s| s.weight), 0.0);
        assert_eq!(draw.samples().count(), 0);
    }
}
