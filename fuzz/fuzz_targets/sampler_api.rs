//! Arbitrary floats into every phase function and every technique's
//! sample / pdf / invert, and every method's draw through the front ends'
//! `Setup`, in f32 and f64: no panic, and every returned density, weight,
//! point and uniform number is finite (densities and weights ≥ 0, uniforms
//! in [0, 1], angles in [0, π]).
#![no_main]

use libfuzzer_sys::fuzz_target;
use omnee_core::{Real, Vector};
use omnee_core::medium::Region;
use omnee_core::method::{Method, Setup};
use omnee_core::mis::{Heuristic, OmneeMis, OneSample, multi_sample_weight};
use omnee_core::phase::{
    Deflection, Draine, FournierForand, HenyeyGreenstein, Isotropic, Mie, Phase, PhaseFunction,
    Rayleigh, TwoTermHg,
};
use omnee_core::sampling::{
    Connection, Directions, Distance, Draw, Equiangular, Omnee, Technique,
};

/// Reads the input as little-endian f64s (cycling, so short inputs work).
struct Floats<'a> {
    data: &'a [u8],
    at: usize,
}

impl Floats<'_> {
    fn next(&mut self) -> f64 {
        if self.data.len() < 8 {
            return 0.5;
        }
        if self.at + 8 > self.data.len() {
            self.at = 0;
        }
        let bytes: [u8; 8] = self.data[self.at..self.at + 8].try_into().unwrap();
        self.at += 8;
        f64::from_le_bytes(bytes)
    }
    fn byte(&mut self) -> u8 {
        (self.next().to_bits() & 0xff) as u8
    }
}

fn vec3<F: Real>(f: &mut Floats) -> F::Vec3 {
    F::Vec3::new(
        F::from_f64(f.next()),
        F::from_f64(f.next()),
        F::from_f64(f.next()),
    )
}

fn phase<F: Real>(f: &mut Floats) -> Option<Phase<'static, F>> {
    let c = |x: f64| F::from_f64(x);
    Some(match f.byte() % 8 {
        0 => Phase::Isotropic(Isotropic),
        1 => Phase::HenyeyGreenstein(HenyeyGreenstein::new(c(f.next())).ok()?),
        2 => Phase::TwoTermHg(TwoTermHg::two_term(c(f.next()), c(f.next()), c(f.next())).ok()?),
        3 => Phase::Draine(Draine::new(c(f.next()), c(f.next())).ok()?),
        4 => Phase::FournierForand(FournierForand::new(c(f.next()), c(f.next())).ok()?),
        5 => Phase::Mie(Mie::new(c(f.next())).ok()?),
        6 => Phase::Rayleigh(Rayleigh),
        _ => Phase::HenyeyGreenstein(HenyeyGreenstein::new(c(0.9999)).ok()?),
    })
}

fn ok<F: Real>(x: F) -> bool {
    x.is_finite() && x >= F::ZERO
}

fn check_phase<F: Real>(p: &Phase<'static, F>, f: &mut Floats) {
    let u = F::from_f64(f.next());
    if u >= F::ZERO && u < F::ONE {
        let d = p.sample(u);
        assert!(d.is_finite() && d.theta >= F::ZERO && d.theta <= F::PI, "{p:?} sample({u:?}) = {d:?}");
        assert!(ok(p.eval(d)) && ok(p.pdf(d)), "{p:?} at {d:?}");
        let c = p.cdf(d);
        assert!(c >= F::ZERO && c <= F::ONE, "{p:?} cdf {c:?}");
    }
    for d in [
        Deflection::from_theta(F::from_f64(f.next())),
        Deflection::from_cos(F::from_f64(f.next())),
        Deflection::from_one_minus_cos(F::from_f64(f.next())),
    ] {
        assert!(ok(p.eval(d)) && ok(p.pdf(d)), "{p:?} at {d:?}: {:?}", p.eval(d));
        let c = p.cdf(d);
        assert!(c >= F::ZERO && c <= F::ONE, "{p:?} cdf({d:?}) = {c:?}");
        if let Some(u) = p.invert(d) {
            assert!(u >= F::ZERO && u <= F::ONE, "{p:?} invert({d:?}) = {u:?}");
        }
    }
    let m = p.mean_cosine();
    assert!(m.is_finite() && m.abs() <= F::ONE, "{p:?} mean cosine {m:?}");
}

fn check_technique<F: Real>(t: &dyn Technique<F>, name: &str, f: &mut Floats) {
    let u = [F::from_f64(f.next()), F::from_f64(f.next()), F::from_f64(f.next())];
    let in_range = u.iter().all(|&x| x >= F::ZERO && x < F::ONE);
    if let Some(s) = t.sample(u) {
        assert!(
            s.x1.is_finite() && ok(s.pdf) && ok(s.weight),
            "{name}: sample({u:?}) = {s:?} (u in range: {in_range})"
        );
        let p = t.pdf(s.x1);
        assert!(ok(p), "{name}: pdf(sample) = {p:?}");
    }
    let x1 = vec3::<F>(f);
    let p = t.pdf(x1);
    assert!(ok(p), "{name}: pdf({x1:?}) = {p:?}");
    if let Some(v) = t.invert(x1) {
        assert!(v.iter().all(|&x| x >= F::ZERO && x <= F::ONE), "{name}: invert({x1:?}) = {v:?}");
    }
}

/// OmneeMis's pair of vertices from six fuzzed numbers, and its density at
/// them and at a fuzzed point: finite, non-negative.
fn check_omnee_mis<F: Real, P: PhaseFunction<F>>(mis: &OmneeMis<'_, F, P>, f: &mut Floats) {
    for s in mis.draw(|| F::from_f64(f.next())).samples() {
        assert!(s.x1.is_finite() && ok(s.pdf) && ok(s.weight), "OmneeMis: {s:?}");
        let p = mis.pdf(s.x1);
        assert!(ok(p), "OmneeMis: pdf(sample) = {p:?}");
    }
    let p = mis.pdf(vec3::<F>(f));
    assert!(ok(p), "OmneeMis: pdf = {p:?}");
}

fn run<F: Real>(f: &mut Floats) {
    let Some(p) = phase::<F>(f) else { return };
    check_phase(&p, f);
    let (x0, x2) = (vec3::<F>(f), vec3::<F>(f));
    let Ok(c) = Connection::new(x0, x2, F::from_f64(f.next())) else { return };
    let k = c.kernel(&p, vec3::<F>(f));
    assert!(ok(k), "kernel {k:?}");
    let dirs = if f.byte() % 2 == 0 {
        Directions::Sphere
    } else {
        match Directions::cosine(vec3::<F>(f)) {
            Ok(d) => d,
            Err(_) => return,
        }
    };
    let region = if f.byte() % 2 == 0 {
        Region::Everywhere
    } else {
        match Region::slab(F::from_f64(f.next()), F::from_f64(f.next())) {
            Ok(r) => r,
            Err(_) => return,
        }
    };
    let omnee = Omnee::new(c, p);
    let equiangular = Equiangular::new(c, p, dirs, region);
    check_technique(&omnee, "omnee", f);
    check_technique(&equiangular, "equiangular", f);
    let Ok(distance) = Distance::new(c, p, dirs, region, F::from_f64(f.next())) else { return };
    check_technique(&distance, "distance", f);
    let techniques: [&dyn Technique<F>; 3] = [&omnee, &equiangular, &distance];
    let probabilities = [F::from_f64(f.next()), F::from_f64(f.next()), F::from_f64(f.next())];
    let heuristic = if f.byte() % 2 == 0 { Heuristic::Balance } else { Heuristic::Power };
    if let Ok(mis) = OneSample::new(techniques, probabilities, heuristic) {
        check_technique(&mis, "one-sample MIS", f);
    }
    check_omnee_mis(&OmneeMis::recommended(omnee, &equiangular), f);
    let cone = Deflection::from_theta(F::from_f64(f.next()));
    if let Ok(mis) = OmneeMis::new(omnee, &distance, F::from_f64(f.next()), cone) {
        check_omnee_mis(&mis, f);
    }
    let x1 = vec3::<F>(f);
    let counts = [F::ONE, F::TWO, F::HALF];
    for i in 0..3 {
        let w = multi_sample_weight(&techniques, &counts, i, x1, techniques[i].pdf(x1), heuristic);
        assert!(w >= F::ZERO && w <= F::ONE, "multi-sample weight {w:?}");
    }
    check_methods(&p, c, dirs, region, f);
}

/// Every method's draw through `Setup` with a fuzzed σt (refused, or a
/// setup whose draws take at most six numbers and return finite vertices
/// with finite, non-negative densities).
fn check_methods<F: Real>(
    p: &Phase<'static, F>,
    c: Connection<F>,
    dirs: Directions<F>,
    region: Region<F>,
    f: &mut Floats,
) {
    let Ok(setup) = Setup::new(p, dirs, region, F::from_f64(f.next())) else { return };
    for method in Method::ALL {
        let draw = setup.draw(method, c, || F::from_f64(f.next()));
        assert!(draw.taken <= Draw::<F>::MAX_NUMBERS, "{method}: {draw:?}");
        for s in draw.samples() {
            assert!(s.x1.is_finite() && ok(s.pdf) && ok(s.weight), "{method}: {s:?}");
            let pdf = setup.pdf(method, c, s.x1);
            assert!(ok(pdf), "{method}: pdf(sample) = {pdf:?}");
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let mut f = Floats { data, at: 0 };
    run::<f32>(&mut f);
    let mut f = Floats { data, at: 0 };
    run::<f64>(&mut f);
});
