//! The batch over connections (`omnee::sampling::Connections`): every lane
//! is the scalar call on the same inputs, bit for bit, in both precisions,
//! for every phase function family (as the core's `Phase` enum, and
//! table-sampled through its `InverseCdf` where the family has one), and
//! for OMNEE, the recommended MIS and the lobe combination.
//!
//! The lanes mix ordinary connections with the ones a renderer's batch
//! meets at its edges: coincident end points, NaN and infinite
//! coordinates, end points from 1e-30 to 1e30 apart, uniform numbers at 0,
//! at 1 − ulp, out of [0, 1] and NaN; batch lengths straddle the chunks of
//! 64 lanes the f32 path works in. The scalar reference is
//! `Connection::new` then the technique's own sampler, and no vertex where
//! a uniform number is NaN or infinite (the batch's one rule of its own:
//! the scalar samplers clamp a NaN `u0` to 0 and draw a vertex); a lane
//! without a vertex must come back `valid = false` with zeros, any other
//! lane with the same bits of `x1`, pdf and weight. No lane may hold a NaN.

use crate::harness::PhaseSpec;
use omnee::lobe::{LobeMis, PhaseLobe};
use omnee::medium::Region;
use omnee::method::{Method, Setup};
use omnee::phase::{
    Draine, FournierForand, HenyeyGreenstein, InverseCdf, Isotropic, Mie, Mixture, Phase, Rayleigh,
    TableSampled, Tabulated,
};
use omnee::sampling::{
    Connection, Connections, Directions, Omnee, PhaseBatch, Points, PointsMut, Sample,
    SampleArrays, Technique, Uniforms,
};
use omnee::{Error, Real, Vector};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

fn config(cases: u32) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(0x6f6d_6e65_6524),
        failure_persistence: None,
        ..Config::default()
    }
}

/// One lane's inputs in f64 (rounded to the precision under test).
#[derive(Clone, Copy, Debug)]
struct Lane {
    x0: [f64; 3],
    x2: [f64; 3],
    u: [f64; 6],
    incoming: [f64; 3],
}

/// A coordinate: mostly of order 1, now and then at a scale from 1e-30 to
/// 1e30, now and then NaN, ±∞ or a signed zero.
fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![
        12 => -2.0..2.0f64,
        2 => (-30i32..=30, -1.0..1.0f64).prop_map(|(e, m)| m * 10f64.powi(e)),
        1 => prop_oneof![
            Just(f64::NAN),
            Just(f64::INFINITY),
            Just(f64::NEG_INFINITY),
            Just(0.0),
            Just(-0.0),
        ],
    ]
}

fn point() -> impl Strategy<Value = [f64; 3]> {
    [coordinate(), coordinate(), coordinate()]
}

/// A uniform number: mostly in [0, 1), now and then at its edges, NaN or
/// out of range (in [−1, 0), where the azimuth's half turns are odd, or
/// beyond).
fn unit() -> impl Strategy<Value = f64> {
    prop_oneof![
        24 => 0.0..1.0f64,
        1 => Just(0.0),
        1 => Just(1.0 - f64::from(f32::EPSILON) / 2.0),
        1 => Just(f64::NAN),
        1 => -1.0..0.0f64,
        1 => prop_oneof![Just(-0.25), Just(1.0), Just(1.5), Just(-3.0), Just(f64::INFINITY)],
    ]
}

/// A lane: `x2` is `x0` once in twenty, and a point next to it (1e-7 of
/// its size) once in twenty.
fn lane() -> impl Strategy<Value = Lane> {
    (
        point(),
        point(),
        0..20u8,
        [unit(), unit(), unit(), unit(), unit(), unit()],
        point(),
    )
        .prop_map(|(x0, mut x2, kind, u, incoming)| {
            if kind == 0 {
                x2 = x0;
            } else if kind == 1 {
                x2 = x0.map(|c| c * (1.0 + 1e-7) + 1e-7);
            }
            Lane {
                x0,
                x2,
                u,
                incoming,
            }
        })
}

/// 1 to 200 lanes: within one chunk of 64, on its edges and across three.
fn lanes() -> impl Strategy<Value = Vec<Lane>> {
    prop::collection::vec(lane(), 1..200)
}

/// Every family, HG (the vectorised path) weighted up.
fn phase_spec() -> impl Strategy<Value = PhaseSpec> {
    let g = -0.9999..0.9999f64;
    prop_oneof![
        6 => g.clone().prop_map(PhaseSpec::Hg),
        1 => Just(PhaseSpec::Isotropic),
        1 => Just(PhaseSpec::Rayleigh),
        1 => (g.clone(), g.clone(), 0.0..=1.0f64).prop_map(|(a, b, w)| PhaseSpec::TwoTerm(a, b, w)),
        1 => (-0.995..0.995f64, 0.0..=1000.0f64).prop_map(|(g, a)| PhaseSpec::Draine(g, a)),
        1 => (0.001..0.499f64, 1.001..1.5f64).prop_map(|(b, n)| PhaseSpec::Ff(b, n)),
        1 => (0.1..50.0f64).prop_map(PhaseSpec::Mie),
        1 => any::<u64>().prop_map(PhaseSpec::Tabulated),
    ]
}

/// θmax over (0, π], π itself half the time.
fn theta_max() -> impl Strategy<Value = f64> {
    prop_oneof![Just(std::f64::consts::PI), 1e-3..std::f64::consts::PI]
}

/// The spec as the core's run-time phase function (a table's arrays are
/// leaked: a few hundred bytes per case, in a test binary).
fn phase<F: Real>(spec: PhaseSpec) -> Phase<'static, F> {
    let f = F::from_f64;
    match spec {
        PhaseSpec::Isotropic => Phase::Isotropic(Isotropic),
        PhaseSpec::Rayleigh => Phase::Rayleigh(Rayleigh),
        PhaseSpec::Hg(g) => Phase::HenyeyGreenstein(HenyeyGreenstein::new(f(g)).unwrap()),
        PhaseSpec::TwoTerm(a, b, w) => {
            Phase::TwoTermHg(Mixture::two_term(f(a), f(b), f(w)).unwrap())
        }
        PhaseSpec::Draine(g, a) => Phase::Draine(Draine::new(f(g), f(a)).unwrap()),
        PhaseSpec::Ff(b, n) => Phase::FournierForand(FournierForand::new(f(b), f(n)).unwrap()),
        PhaseSpec::Mie(d) => Phase::Mie(Mie::new(f(d)).unwrap()),
        PhaseSpec::Tabulated(seed) => {
            let (edges, values) = crate::harness::phases::table(seed);
            let mut theta: Vec<F> = edges.iter().map(|&t| f(t)).collect();
            *theta.last_mut().unwrap() = F::PI;
            let values: Vec<F> = values.iter().map(|&v| f(v)).collect();
            let cdf = vec![F::ZERO; theta.len()];
            Phase::Tabulated(
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

/// The lanes in structure-of-arrays form, in precision `F`.
struct Soa<F> {
    cols: [Vec<F>; 15],
}

impl<F: Real> Soa<F> {
    fn new(lanes: &[Lane]) -> Self {
        let f = F::from_f64;
        let mut cols: [Vec<F>; 15] = Default::default();
        for l in lanes {
            let values = [
                l.x0,
                l.x2,
                [l.u[0], l.u[1], l.u[2]],
                [l.u[3], l.u[4], l.u[5]],
                l.incoming,
            ];
            for (k, v) in values.iter().flatten().enumerate() {
                cols[k].push(f(*v));
            }
        }
        Self { cols }
    }

    fn connections(&self, theta_max: F) -> Result<Connections<'_, F>, Error> {
        let c = &self.cols;
        Connections::new(
            Points {
                x: &c[0],
                y: &c[1],
                z: &c[2],
            },
            Points {
                x: &c[3],
                y: &c[4],
                z: &c[5],
            },
            theta_max,
        )
    }

    /// Uniform numbers `k` (0: u[0..3], 1: u[3..6]).
    fn uniforms(&self, k: usize) -> Uniforms<'_, F> {
        let c = &self.cols[6 + 3 * k..];
        Uniforms {
            u0: &c[0],
            u1: &c[1],
            u2: &c[2],
        }
    }

    fn incoming(&self) -> Points<'_, F> {
        let c = &self.cols;
        Points {
            x: &c[12],
            y: &c[13],
            z: &c[14],
        }
    }

    fn x0(&self, i: usize) -> F::Vec3 {
        F::Vec3::new(self.cols[0][i], self.cols[1][i], self.cols[2][i])
    }

    fn x2(&self, i: usize) -> F::Vec3 {
        F::Vec3::new(self.cols[3][i], self.cols[4][i], self.cols[5][i])
    }

    fn u(&self, i: usize) -> [F; 6] {
        core::array::from_fn(|k| self.cols[6 + k][i])
    }
}

/// Owned output of a batch.
struct Out<F> {
    x: Vec<F>,
    y: Vec<F>,
    z: Vec<F>,
    pdf: Vec<F>,
    weight: Vec<F>,
    valid: Vec<bool>,
}

impl<F: Real> Out<F> {
    /// `n` lanes filled with a marker that no sampler writes.
    fn new(n: usize) -> Self {
        let marker = F::from_f64(-7.0);
        Self {
            x: vec![marker; n],
            y: vec![marker; n],
            z: vec![marker; n],
            pdf: vec![marker; n],
            weight: vec![marker; n],
            valid: vec![true; n],
        }
    }

    fn samples(&mut self) -> SampleArrays<'_, F> {
        SampleArrays {
            x1: PointsMut {
                x: &mut self.x,
                y: &mut self.y,
                z: &mut self.z,
            },
            pdf: &mut self.pdf,
            weight: &mut self.weight,
            valid: &mut self.valid,
        }
    }

    /// Lane `i` as the scalar call's result, after checking that a lane
    /// without a vertex is all zero and that no number is NaN.
    fn lane(&self, i: usize) -> Option<Sample<F>> {
        let numbers = [self.x[i], self.y[i], self.z[i], self.pdf[i], self.weight[i]];
        assert!(numbers.iter().all(|v| !v.is_nan()), "lane {i}: {numbers:?}");
        if !self.valid[i] {
            assert!(
                numbers.iter().all(|&v| v == F::ZERO),
                "lane {i}: {numbers:?}"
            );
            return None;
        }
        Some(Sample {
            x1: F::Vec3::new(self.x[i], self.y[i], self.z[i]),
            pdf: self.pdf[i],
            weight: self.weight[i],
        })
    }
}

/// Whether the numbers are all finite: a lane with a NaN or infinite
/// uniform number has no vertex (where the scalar sampler would clamp a
/// NaN `u0` to 0 and draw one).
fn finite<F: Real>(u: &[F]) -> bool {
    u.iter().all(|x| x.is_finite())
}

/// The bits of a sample (`None` stays `None`).
fn bits<F: Real>(s: Option<Sample<F>>) -> Option<[u64; 5]> {
    s.map(|s| {
        let [x, y, z] = s.x1.to_array();
        [x, y, z, s.pdf, s.weight].map(|v| v.to_f64().to_bits())
    })
}

/// OMNEE over the lanes against the scalar sampler, lane by lane.
fn check_omnee<F: Real, P: PhaseBatch<F> + Copy>(
    lanes: &[Lane],
    phase: P,
    theta_max: f64,
) -> Result<usize, TestCaseError> {
    let soa = Soa::<F>::new(lanes);
    let theta_max = F::from_f64(theta_max);
    let c = soa.connections(theta_max).unwrap();
    let mut out = Out::new(lanes.len());
    let count = c
        .sample_omnee(&phase, soa.uniforms(0), out.samples())
        .unwrap();
    let mut expected = 0;
    for (i, lane) in lanes.iter().enumerate() {
        let u = soa.u(i);
        let scalar = Connection::new(soa.x0(i), soa.x2(i), theta_max)
            .ok()
            .filter(|_| finite(&u[..3]))
            .and_then(|conn| Omnee::new(conn, phase).sample([u[0], u[1], u[2]]));
        prop_assert_eq!(bits(out.lane(i)), bits(scalar), "lane {}: {:?}", i, lane);
        expected += usize::from(scalar.is_some());
    }
    prop_assert_eq!(count, expected);
    Ok(count)
}

proptest! {
    #![proptest_config(config(384))]

    /// Every lane of `sample_omnee` is `Omnee::sample` of its connection,
    /// in f32 and f64, for the phase function as the core's `Phase` and,
    /// where it has one, through its `InverseCdf`.
    #[test]
    fn omnee_lanes_are_the_scalar_sample_bit_for_bit(
        lanes in lanes(),
        spec in phase_spec(),
        theta_max in theta_max(),
    ) {
        let spec = spec.rounded_to_f32();
        check_omnee::<f32, _>(&lanes, phase::<f32>(spec), theta_max)?;
        check_omnee::<f64, _>(&lanes, phase::<f64>(spec), theta_max)?;
        if spec.inverse_cdf() && !matches!(spec, PhaseSpec::Hg(_) | PhaseSpec::Isotropic) {
            let (p32, p64) = (phase::<f32>(spec), phase::<f64>(spec));
            // (A table with an empty bin has no inverse CDF to build.)
            if let (Ok(t32), Ok(t64)) = (InverseCdf::new(&p32), InverseCdf::new(&p64)) {
                check_omnee::<f32, _>(&lanes, TableSampled::new(p32, &t32), theta_max)?;
                check_omnee::<f64, _>(&lanes, TableSampled::new(p64, &t64), theta_max)?;
            }
        }
    }

    /// The same for Henyey–Greenstein as its own type (the vectorised
    /// inverse CDF without the enum around it), at the g of a forward peak
    /// whose samples often fall below the sinc series threshold.
    #[test]
    fn hg_lanes_are_the_scalar_sample_bit_for_bit(
        lanes in lanes(),
        g in prop_oneof![-0.9999..0.9999f64, 0.99..0.99999f64],
        theta_max in theta_max(),
    ) {
        let g32 = HenyeyGreenstein::new(g as f32).unwrap();
        check_omnee::<f32, _>(&lanes, g32, theta_max)?;
        check_omnee::<f64, _>(&lanes, HenyeyGreenstein::new(g).unwrap(), theta_max)?;
    }
}

/// How rays leave `x2` for the MIS companion, and the medium region.
fn rays() -> impl Strategy<Value = (Option<[f64; 3]>, Option<(f64, f64)>)> {
    (
        prop::option::of(
            [-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64]
                .prop_filter("non-zero", |n| n.iter().any(|c| c.abs() > 1e-3)),
        ),
        prop::option::of((-3.0..3.0f64, 0.05..4.0f64).prop_map(|(lo, w)| (lo, lo + w))),
    )
}

/// The recommended MIS over the lanes against `Setup::draw` lane by lane.
fn check_mis<F: Real>(
    lanes: &[Lane],
    spec: PhaseSpec,
    normal: Option<[f64; 3]>,
    slab: Option<(f64, f64)>,
) -> Result<usize, TestCaseError> {
    let f = F::from_f64;
    let soa = Soa::<F>::new(lanes);
    let c = soa.connections(F::PI).unwrap();
    let directions = normal.map_or(Directions::Sphere, |[x, y, z]| {
        Directions::cosine(F::Vec3::new(f(x), f(y), f(z))).unwrap()
    });
    let region = slab.map_or(Region::Everywhere, |(lo, hi)| {
        Region::slab(f(lo), f(hi)).unwrap()
    });
    let setup = Setup::new(phase::<F>(spec), directions, region, F::ONE).unwrap();
    let (mut o, mut k) = (Out::new(lanes.len()), Out::new(lanes.len()));
    let count = c
        .sample_mis(
            &setup,
            soa.uniforms(0),
            soa.uniforms(1),
            o.samples(),
            k.samples(),
        )
        .unwrap();
    let mut expected = 0;
    for (i, lane) in lanes.iter().enumerate() {
        let u = soa.u(i);
        let want = match Connection::new(soa.x0(i), soa.x2(i), F::PI) {
            Ok(conn) if finite(&u) => {
                let mut next = u.into_iter();
                setup
                    .draw(Method::Mis, conn, || next.next().unwrap())
                    .vertices
            }
            _ => [None, None],
        };
        prop_assert_eq!(bits(o.lane(i)), bits(want[0]), "lane {}: {:?}", i, lane);
        prop_assert_eq!(bits(k.lane(i)), bits(want[1]), "lane {}: {:?}", i, lane);
        expected += want.iter().flatten().count();
    }
    prop_assert_eq!(count, expected);
    Ok(count)
}

/// The lobe combination over the lanes against `LobeMis::recommended`.
fn check_lobe<F: Real>(lanes: &[Lane], g0: f64, g1: f64) -> Result<usize, TestCaseError> {
    let soa = Soa::<F>::new(lanes);
    let c = soa.connections(F::PI).unwrap();
    let (lobe_phase, phase) = (
        HenyeyGreenstein::new(F::from_f64(g0)).unwrap(),
        HenyeyGreenstein::new(F::from_f64(g1)).unwrap(),
    );
    let mut out = Out::new(lanes.len());
    let count = c
        .sample_lobe_mis(
            lobe_phase,
            soa.incoming(),
            phase,
            soa.uniforms(0),
            out.samples(),
        )
        .unwrap();
    for (i, lane) in lanes.iter().enumerate() {
        let want = Connection::new(soa.x0(i), soa.x2(i), F::PI)
            .ok()
            .filter(|_| finite(&soa.u(i)[..3]))
            .and_then(|conn| {
                let incoming = soa.incoming();
                let w = F::Vec3::new(incoming.x[i], incoming.y[i], incoming.z[i]);
                let lobe = PhaseLobe::new(lobe_phase, w).ok()?;
                let u = soa.u(i);
                LobeMis::recommended(conn, lobe, phase).sample([u[0], u[1], u[2]])
            });
        prop_assert_eq!(bits(out.lane(i)), bits(want), "lane {}: {:?}", i, lane);
    }
    Ok(count)
}

proptest! {
    #![proptest_config(config(128))]

    /// Every lane of `sample_mis` is the recommended MIS draw
    /// (`Setup::draw` with `Method::Mis`) of its connection, both vertices,
    /// with sphere or cosine directions, everywhere or in a slab.
    #[test]
    fn mis_lanes_are_the_scalar_draw_bit_for_bit(
        lanes in lanes(),
        spec in phase_spec(),
        (normal, slab) in rays(),
    ) {
        let spec = spec.rounded_to_f32();
        check_mis::<f32>(&lanes, spec, normal, slab)?;
        check_mis::<f64>(&lanes, spec, normal, slab)?;
    }

    /// Every lane of `sample_lobe_mis` is `LobeMis::recommended`'s sample
    /// for its connection and incoming direction.
    #[test]
    fn lobe_lanes_are_the_scalar_combination_bit_for_bit(
        lanes in lanes(),
        g0 in -0.99..0.99f64,
        g1 in -0.99..0.99f64,
    ) {
        check_lobe::<f32>(&lanes, g0, g1)?;
        check_lobe::<f64>(&lanes, g0, g1)?;
    }
}

/// Lengths that disagree are `Error::Arrays` (field "connections") and
/// leave the outputs as they were; a θmax outside (0, π] is the scalar
/// constructor's error.
#[test]
fn mismatched_lengths_and_a_bad_theta_max_are_errors_that_write_nothing() {
    let lanes: Vec<Lane> = (0..70)
        .map(|i| Lane {
            x0: [0.0, 0.0, 1.0],
            x2: [0.1 * i as f64, 0.0, 0.0],
            u: [0.5; 6],
            incoming: [0.0, 0.0, 1.0],
        })
        .collect();
    let soa = Soa::<f32>::new(&lanes);
    for bad in [0.0f32, -1.0, 4.0, f32::NAN] {
        let e = soa.connections(bad).unwrap_err();
        assert_eq!(e.field(), "theta_max", "{bad}");
    }
    let short = &soa.cols[0][..69];
    let e = Connections::new(
        Points {
            x: short,
            y: &soa.cols[1],
            z: &soa.cols[2],
        },
        Points {
            x: &soa.cols[3],
            y: &soa.cols[4],
            z: &soa.cols[5],
        },
        1.0,
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            Error::Arrays {
                field: "connections",
                ..
            }
        ),
        "{e:?}"
    );
    let c = soa.connections(1.0).unwrap();
    let hg = HenyeyGreenstein::new(0.5f32).unwrap();
    let setup = Setup::new(hg, Directions::Sphere, Region::Everywhere, 1.0).unwrap();
    let u = soa.uniforms(0);
    let short_u = Uniforms {
        u0: u.u0,
        u1: &u.u1[..69],
        u2: u.u2,
    };
    let untouched =
        |o: &Out<f32>| o.pdf.iter().chain(&o.x).all(|&v| v == -7.0) && o.valid.iter().all(|&v| v);
    let mut out = Out::<f32>::new(70);
    assert!(matches!(
        c.sample_omnee(&hg, short_u, out.samples()),
        Err(Error::Arrays { .. })
    ));
    assert!(untouched(&out));
    let mut short_out = Out::<f32>::new(69);
    assert!(c.sample_omnee(&hg, u, short_out.samples()).is_err());
    assert!(untouched(&short_out));
    let (mut o, mut k) = (Out::<f32>::new(70), Out::<f32>::new(69));
    assert!(
        c.sample_mis(&setup, u, u, o.samples(), k.samples())
            .is_err()
    );
    assert!(untouched(&o) && untouched(&k));
    let mut o = Out::<f32>::new(70);
    let incoming = Points {
        x: short,
        y: &soa.cols[13],
        z: &soa.cols[14],
    };
    assert!(c.sample_lobe_mis(hg, incoming, hg, u, o.samples()).is_err());
    assert!(untouched(&o));
    // An empty batch is a valid one.
    let empty = Soa::<f32>::new(&[]);
    let c = empty.connections(1.0).unwrap();
    let mut out = Out::<f32>::new(0);
    assert_eq!(c.sample_omnee(&hg, empty.uniforms(0), out.samples()), Ok(0));
}

/// A batch of the benchmark's kind samples most lanes (the comparisons
/// above are not vacuous) and, for HG in f32, leaves next to none to the
/// scalar fallback: `|u2| ≤ 1` everywhere here, so every lane goes through
/// the SIMD stages and still equals the scalar sample.
#[test]
fn ordinary_lanes_all_have_vertices() {
    let mut rng = crate::harness::Rng::new(24);
    let lanes: Vec<Lane> = (0..1000)
        .map(|_| Lane {
            x0: [
                rng.range(-0.5, 0.5),
                rng.range(-0.5, 0.5),
                rng.range(0.5, 1.5),
            ],
            x2: [
                rng.range(-0.5, 0.5),
                rng.range(-0.5, 0.5),
                rng.range(-0.5, 0.5),
            ],
            u: core::array::from_fn(|_| rng.uniform::<f64>()),
            incoming: [0.0, 0.0, 1.0],
        })
        .collect();
    let hg = HenyeyGreenstein::new(0.9f32).unwrap();
    let count = check_omnee::<f32, _>(&lanes, hg, std::f64::consts::PI).unwrap();
    assert!(count >= 995, "{count}");
}
