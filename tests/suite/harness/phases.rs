//! The phase functions under test, as data: one list instantiates in either
//! precision, and random tables stand in for measured ones.

use super::Rng;
use omnee::Real;
use omnee::phase::{
    Draine, FournierForand, HenyeyGreenstein, Isotropic, Mie, Mixture, PhaseFunction, Rayleigh,
    Tabulated,
};

/// The phase functions of the suite, as data, so one list instantiates in
/// either precision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PhaseSpec {
    /// `1/(4π)`.
    Isotropic,
    /// Rayleigh, `3/(16π)(1 + cos²θ)`.
    Rayleigh,
    /// Henyey–Greenstein with g.
    Hg(f64),
    /// `w·HG(g1) + (1 − w)·HG(g2)`.
    TwoTerm(f64, f64, f64),
    /// Draine with (g, α).
    Draine(f64, f64),
    /// Fournier–Forand with (backscatter fraction B, refractive index n).
    Ff(f64, f64),
    /// Approximate Mie for a droplet diameter in µm.
    Mie(f64),
    /// A measured-style table: the random bins of [`table`] for this seed.
    Tabulated(u64),
}

impl PhaseSpec {
    /// The phase function in precision `F` (panics on invalid parameters:
    /// every spec in the suite is valid).
    pub fn build<F: Real>(self) -> Box<dyn PhaseFunction<F>> {
        let f = F::from_f64;
        match self {
            PhaseSpec::Isotropic => Box::new(Isotropic),
            PhaseSpec::Rayleigh => Box::new(Rayleigh),
            PhaseSpec::Hg(g) => Box::new(HenyeyGreenstein::new(f(g)).unwrap()),
            PhaseSpec::TwoTerm(g1, g2, w) => {
                Box::new(Mixture::two_term(f(g1), f(g2), f(w)).unwrap())
            }
            PhaseSpec::Draine(g, a) => Box::new(Draine::new(f(g), f(a)).unwrap()),
            PhaseSpec::Ff(b, n) => Box::new(FournierForand::new(f(b), f(n)).unwrap()),
            PhaseSpec::Mie(d) => Box::new(Mie::new(f(d)).unwrap()),
            PhaseSpec::Tabulated(seed) => {
                // The table borrows its arrays: leak them (a few hundred bytes
                // per call, in a test binary).
                let (edges, values) = table(seed);
                let mut theta: Vec<F> = edges.iter().map(|&t| f(t)).collect();
                *theta.last_mut().unwrap() = F::PI;
                let values: Vec<F> = values.iter().map(|&v| f(v)).collect();
                let cdf = vec![F::ZERO; theta.len()];
                Box::new(
                    Tabulated::new(
                        Box::leak(theta.into_boxed_slice()),
                        Box::leak(values.into_boxed_slice()),
                        Box::leak(cdf.into_boxed_slice()),
                    )
                    .unwrap(),
                )
            }
        }
    }

    /// The same spec with every parameter rounded to f32, so an f64 instance
    /// has exactly the parameters of the f32 one (1 − g for g = 0.9999 moves
    /// by 6e-4 relative in the rounding alone).
    pub fn rounded_to_f32(self) -> Self {
        let r = |x: f64| x as f32 as f64;
        match self {
            PhaseSpec::Hg(g) => PhaseSpec::Hg(r(g)),
            PhaseSpec::TwoTerm(a, b, w) => PhaseSpec::TwoTerm(r(a), r(b), r(w)),
            PhaseSpec::Draine(g, a) => PhaseSpec::Draine(r(g), r(a)),
            PhaseSpec::Ff(b, n) => PhaseSpec::Ff(r(b), r(n)),
            PhaseSpec::Mie(d) => PhaseSpec::Mie(r(d)),
            other => other,
        }
    }

    /// Where the density jumps inside (0, π): the interior bin edges of a
    /// table. Quadrature must split there: a jump between two nodes of a
    /// Gauss–Kronrod panel can go unnoticed by its error estimate (measured:
    /// a cdf off by 8e-4 without the split).
    pub fn breakpoints(self) -> Vec<f64> {
        match self {
            PhaseSpec::Tabulated(seed) => {
                let (edges, _) = table(seed);
                edges[1..edges.len() - 1].to_vec()
            }
            _ => Vec::new(),
        }
    }

    /// Whether `sample` is the inverse of `cdf` (false for mixtures, which
    /// spend part of `u` on the lobe choice).
    pub fn inverse_cdf(self) -> bool {
        !matches!(self, PhaseSpec::TwoTerm(..) | PhaseSpec::Mie(..))
    }
}

/// The bins of [`PhaseSpec::Tabulated`]: 1 to 12 bins whose edges crowd
/// towards θ = 0 (a forward peak) or spread evenly, with values spanning four
/// orders of magnitude and about one bin in five empty (never all). Edges
/// are at least 1e-4 apart, so they stay distinct in f32.
pub fn table(seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut rng = Rng::new(seed ^ 0x7ab1_e5ee_d000_0000);
    let bins = 1 + (rng.next_u64() % 12) as usize;
    let crowd = rng.uniform::<f64>() < 0.5;
    let mut interior: Vec<f64> = (1..bins)
        .map(|_| {
            let w = rng.range(0.0, 1.0);
            core::f64::consts::PI * if crowd { w * w * w } else { w }
        })
        .collect();
    interior.sort_by(f64::total_cmp);
    let mut edges = vec![0.0];
    for t in interior {
        if t - edges.last().unwrap() > 1e-4 && core::f64::consts::PI - t > 1e-4 {
            edges.push(t);
        }
    }
    edges.push(core::f64::consts::PI);
    let mut values: Vec<f64> = (1..edges.len())
        .map(|_| {
            if rng.uniform::<f64>() < 0.2 {
                0.0
            } else {
                10f64.powf(rng.range(-2.0, 2.0))
            }
        })
        .collect();
    if values.iter().all(|&v| v == 0.0) {
        values[0] = 1.0;
    }
    (edges, values)
}
