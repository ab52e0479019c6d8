//! The vectorised batch entry point `Omnee::sample_batch` in the shape the
//! tests need: owned structure-of-arrays output, and one lane as a scalar
//! [`omnee::sampling::Technique`].

use glam::DVec3;
use omnee::phase::HenyeyGreenstein;

/// The output of [`BatchOmnee::batch`]: per lane `x1 = (x, y, z)`, pdf and
/// weight (zeros where no sample), and the number of samples returned.
pub struct Lanes {
    pub x: Vec<f32>,
    pub y: Vec<f32>,
    pub z: Vec<f32>,
    pub pdf: Vec<f32>,
    pub weight: Vec<f32>,
    pub count: usize,
}

/// The batch entry point `Omnee::sample_batch` (f32, Henyey–Greenstein) seen
/// as a scalar [`Technique<f64>`]: each `sample` runs a batch of one lane
/// (with `u` rounded to f32), `pdf` is the f64 OMNEE density of the same
/// connection and g, so a χ² test compares the batch's points with the
/// density they should have.
pub struct BatchOmnee {
    pub f32: omnee::sampling::Omnee<f32, HenyeyGreenstein<f32>>,
    pub f64: omnee::sampling::Omnee<f64, HenyeyGreenstein<f64>>,
}

impl BatchOmnee {
    /// For the end points and θmax rounded to f32 and g rounded to f32, in
    /// both precisions (one geometry, one phase function).
    pub fn new(x0: DVec3, x2: DVec3, theta_max: f64, g: f64) -> Self {
        use omnee::sampling::{Connection, Omnee};
        let c32 = Connection::new(x0.as_vec3(), x2.as_vec3(), theta_max as f32).unwrap();
        let c64 = Connection::new(
            c32.axis.x0.as_dvec3(),
            c32.axis.x2.as_dvec3(),
            f64::from(c32.theta_max),
        )
        .unwrap();
        let g32 = g as f32;
        Self {
            f32: Omnee::new(c32, HenyeyGreenstein::new(g32).unwrap()),
            f64: Omnee::new(c64, HenyeyGreenstein::new(f64::from(g32)).unwrap()),
        }
    }

    /// One `sample_batch` call in f32 over the uniforms `u0`, `u1`, `u2`
    /// (equal lengths), its output in owned structure-of-arrays form.
    pub fn batch(&self, u0: &[f32], u1: &[f32], u2: &[f32]) -> Lanes {
        use omnee::sampling::{Uniforms, Vertices};
        let m = u0.len();
        let mut out = Lanes {
            x: vec![0.0; m],
            y: vec![0.0; m],
            z: vec![0.0; m],
            pdf: vec![0.0; m],
            weight: vec![0.0; m],
            count: 0,
        };
        out.count = self
            .f32
            .sample_batch(
                Uniforms { u0, u1, u2 },
                Vertices {
                    x: &mut out.x,
                    y: &mut out.y,
                    z: &mut out.z,
                    pdf: &mut out.pdf,
                    weight: &mut out.weight,
                },
            )
            .unwrap();
        out
    }

    /// One lane of the batch: `(x1, pdf, weight)`, or `None` where the batch
    /// reports no sample (pdf = weight = 0).
    pub fn lane(&self, u: [f32; 3]) -> Option<(glam::Vec3, f32, f32)> {
        let l = self.batch(&[u[0]], &[u[1]], &[u[2]]);
        if l.count == 0 {
            assert!(
                l.pdf[0] == 0.0 && l.weight[0] == 0.0,
                "no sample but pdf {} weight {}",
                l.pdf[0],
                l.weight[0]
            );
            return None;
        }
        Some((
            glam::Vec3::new(l.x[0], l.y[0], l.z[0]),
            l.pdf[0],
            l.weight[0],
        ))
    }
}

impl omnee::sampling::Technique<f64> for BatchOmnee {
    fn sample(&self, u: [f64; 3]) -> Option<omnee::sampling::Sample<f64>> {
        let (x1, pdf, weight) = self.lane(u.map(|x| x as f32))?;
        Some(omnee::sampling::Sample {
            x1: x1.as_dvec3(),
            pdf: f64::from(pdf),
            weight: f64::from(weight),
        })
    }
    fn pdf(&self, x1: DVec3) -> f64 {
        self.f64.pdf(x1)
    }
    fn invert(&self, _x1: DVec3) -> Option<[f64; 3]> {
        None
    }
}
