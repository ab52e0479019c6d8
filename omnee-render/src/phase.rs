//! Phase function specs (`iso`, `hg:G`, `tthg:G1,G2,W`, `ff:B,N`,
//! `draine:G,ALPHA`, `mie:DIAMETER_UM`, `rayleigh`, `table:FILE.csv`), parsed
//! by the core's [`Spec`]; this module only reads the CSV of `table:`.
//!
//! A table file has one `angle_deg,value` pair per line (blank lines, lines
//! starting with `#` and a non-numeric header line are skipped): the phase
//! function's relative value at that deflection angle, angles strictly
//! increasing in [0, 180]. The core's [`Tabulated`] needs bins; bin `i`
//! spans from the midpoint with the previous angle to the midpoint with the
//! next one (the first starts at 0°, the last ends at 180°), with the value
//! of its angle: nearest-neighbour in θ, normalised by the core.
//!
//! The renderer draws deflections through [`PhaseSpec::sampled`]: phase
//! functions without a fast exact inverse (Fournier–Forand, Draine,
//! approximate Mie, Rayleigh, tables) through the core's [`InverseCdf`],
//! built once per medium, with the ratio `p/q` in every weight
//! (docs/math.md §11); isotropic, HG and two-term HG exactly.

use crate::error::{RenderError, Result, core_error};
use omnee_core::Real;
use omnee_core::names::Named;
use omnee_core::phase::{
    Deflection, InverseCdf, Phase, PhaseFunction, Spec, TableSampled, Tabulated,
};
use omnee_core::sampling::{Deflections, PhaseBatch};
use std::fmt;

/// A validated phase function spec: the text, and the table if it names one.
#[derive(Clone, Debug)]
pub struct PhaseSpec {
    text: String,
    /// Bin edges (radians, `n + 1`) and values (`n`) of a `table:` spec.
    table: Option<(Vec<f64>, Vec<f64>)>,
}

/// Owned storage for a phase function's tables in precision `F`: the core's
/// [`Tabulated`] borrows its bins from the caller, and [`TableSampled`] its
/// [`InverseCdf`] (5.6 KiB in f32).
#[derive(Debug, Default)]
pub struct TableStorage<F> {
    theta: Vec<F>,
    values: Vec<F>,
    cdf: Vec<F>,
    inverse_cdf: Option<InverseCdf<F>>,
}

/// How a renderer draws deflections from the medium's phase function
/// (`--phase-sampling`). Either way the estimates are unbiased; `table` is
/// faster for the phase functions it tabulates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PhaseSampling {
    /// Fournier–Forand, Draine, Mie, Rayleigh and measured tables through a
    /// 128-bin inverse CDF built once per medium, with `p/q` in the weight
    /// (docs/math.md §11); isotropic, HG and two-term HG exactly.
    Table,
    /// Every phase function by its own exact sampler.
    Exact,
}

impl Named for PhaseSampling {
    const ALL: &'static [Self] = &[PhaseSampling::Table, PhaseSampling::Exact];
    fn name(self) -> &'static str {
        match self {
            PhaseSampling::Table => "table",
            PhaseSampling::Exact => "exact",
        }
    }
    fn help(self) -> &'static str {
        match self {
            PhaseSampling::Table => {
                "Fournier-Forand, Draine, Mie, Rayleigh and measured tables through a 128-bin inverse CDF built once per medium, with p/q in the weight (docs/math.md §11); iso, HG and two-term HG exactly"
            }
            PhaseSampling::Exact => "every phase function by its own exact sampler",
        }
    }
}

omnee_core::display_by_name!(PhaseSampling);

/// A phase function as a renderer samples it: by its own sampler, or
/// through its tabulated inverse CDF ([`TableSampled`]: `eval` is `p`,
/// `sample`/`pdf` are the table's `q`, `sample_ratio` carries `p/q`).
/// Every method dispatches to the variant's own.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sampled<'a, F> {
    /// `p` drawn exactly.
    Exact(Phase<'a, F>),
    /// `p` drawn from its table `q`.
    Table(TableSampled<'a, F, Phase<'a, F>>),
}

impl<'a, F: Real> Sampled<'a, F> {
    /// The phase function `p` itself (exactly sampled), whichever way this
    /// draws it.
    pub fn phase(&self) -> &Phase<'a, F> {
        match self {
            Sampled::Exact(p) => p,
            Sampled::Table(t) => t.phase(),
        }
    }

    /// Whether deflections come from the table.
    pub fn is_tabulated(&self) -> bool {
        matches!(self, Sampled::Table(_))
    }
}

impl<'a, F> From<Phase<'a, F>> for Sampled<'a, F> {
    /// Exact sampling.
    fn from(phase: Phase<'a, F>) -> Self {
        Sampled::Exact(phase)
    }
}

/// Calls `$call` on whichever sampler `$self` holds.
macro_rules! dispatch {
    ($self:expr, $p:ident => $call:expr) => {
        match $self {
            Sampled::Exact($p) => $call,
            Sampled::Table($p) => $call,
        }
    };
}

/// A batch of deflections by the variant's own sampler (Henyey–Greenstein's
/// vectorised in f32).
impl<F: Real> PhaseBatch<F> for Sampled<'_, F> {
    #[inline]
    fn sample_ratio_batch(&self, u0: &[F], out: Deflections<'_, F>) {
        dispatch!(self, p => p.sample_ratio_batch(u0, out))
    }
}

impl<F: Real> PhaseFunction<F> for Sampled<'_, F> {
    #[inline]
    fn eval(&self, d: Deflection<F>) -> F {
        dispatch!(self, p => p.eval(d))
    }
    #[inline]
    fn sample(&self, u: F) -> Deflection<F> {
        dispatch!(self, p => p.sample(u))
    }
    #[inline]
    fn cdf(&self, d: Deflection<F>) -> F {
        dispatch!(self, p => p.cdf(d))
    }
    #[inline]
    fn mean_cosine(&self) -> F {
        dispatch!(self, p => p.mean_cosine())
    }
    #[inline]
    fn pdf(&self, d: Deflection<F>) -> F {
        dispatch!(self, p => p.pdf(d))
    }
    #[inline]
    fn sample_pdf(&self, u: F) -> (Deflection<F>, F) {
        dispatch!(self, p => p.sample_pdf(u))
    }
    #[inline]
    fn sample_ratio(&self, u: F) -> (Deflection<F>, F, F) {
        dispatch!(self, p => p.sample_ratio(u))
    }
    #[inline]
    fn samples_exactly(&self) -> bool {
        dispatch!(self, p => p.samples_exactly())
    }
    #[inline]
    fn invert(&self, d: Deflection<F>) -> Option<F> {
        dispatch!(self, p => p.invert(d))
    }
    #[inline]
    fn backscatter_fraction(&self) -> F {
        dispatch!(self, p => p.backscatter_fraction())
    }
}

/// Whether `table` sampling tabulates `phase`: the phase functions whose
/// exact sampler costs more than a table lookup (a Newton inversion, a
/// mixture's two lobes, a cubic's roots, a binary search over bins).
fn tabulates<F>(phase: &Phase<'_, F>) -> bool {
    matches!(
        phase,
        Phase::FournierForand(_)
            | Phase::Draine(_)
            | Phase::Mie(_)
            | Phase::Rayleigh(_)
            | Phase::Tabulated(_)
    )
}

impl PhaseSpec {
    /// Parses `text`; a `table:` spec reads and checks its CSV file now.
    pub fn parse(text: &str) -> Result<Self> {
        let spec = Spec::<f64>::parse(text).map_err(|e| spec_error(text, e))?;
        let table = match spec {
            Spec::Analytic(_) => None,
            Spec::Table { path } => Some(read_table(path)?),
        };
        let spec = Self {
            text: text.trim().to_string(),
            table,
        };
        // Build once in both precisions so that a table the core rejects
        // fails here, with its field named, and not in the middle of a run.
        spec.instantiate::<f32>(&mut TableStorage::default())?;
        spec.instantiate::<f64>(&mut TableStorage::default())?;
        Ok(spec)
    }

    /// A measured table given as arrays, as a renderer that holds its own
    /// tables hands it over: `theta`, the `n + 1` bin edges in radians
    /// (strictly increasing from 0 to π), and `values`, the `n` bin values
    /// (≥ 0, not all 0; the density is constant per solid angle within a
    /// bin and normalised by the core, [`Tabulated`]). Checked as a
    /// `table:` file is; its spec text is `table`.
    pub fn table(theta: Vec<f64>, values: Vec<f64>) -> Result<Self> {
        // The last edge is set to π in each precision when the table is
        // built (a file's ends at 180°); a caller's array must end there.
        if let Some(&last) = theta.last() {
            let pi = std::f64::consts::PI;
            if !((last - pi).abs() <= 4.0 * f64::EPSILON * pi) {
                return Err(RenderError::Input(format!(
                    "phase table: theta: the last edge is {last}; allowed: pi (the bins cover [0, pi])"
                )));
            }
        }
        let spec = Self {
            text: "table".to_string(),
            table: Some((theta, values)),
        };
        spec.instantiate::<f32>(&mut TableStorage::default())?;
        spec.instantiate::<f64>(&mut TableStorage::default())?;
        Ok(spec)
    }

    /// The bin edges (radians) and values of a table, `None` for the
    /// analytic phase functions.
    pub fn bins(&self) -> Option<(&[f64], &[f64])> {
        self.table
            .as_ref()
            .map(|(theta, values)| (theta.as_slice(), values.as_slice()))
    }

    /// The phase function in precision `F`, borrowing `storage` for a table.
    pub fn instantiate<'a, F: Real>(
        &self,
        storage: &'a mut TableStorage<F>,
    ) -> Result<Phase<'a, F>> {
        let TableStorage {
            theta, values, cdf, ..
        } = storage;
        self.instantiate_in(theta, values, cdf)
    }

    /// The phase function in precision `F` as a renderer samples it with
    /// `sampling`, borrowing `storage` for its tables: with
    /// [`PhaseSampling::Table`], Fournier–Forand, Draine, Mie, Rayleigh and
    /// measured tables are drawn through their [`InverseCdf`], built here
    /// (once per medium); where the table cannot be built (a density of 0
    /// at one of its nodes, as a measured table with zeros may have),
    /// exactly.
    pub fn sampled<'a, F: Real>(
        &self,
        sampling: PhaseSampling,
        storage: &'a mut TableStorage<F>,
    ) -> Result<Sampled<'a, F>> {
        let TableStorage {
            theta,
            values,
            cdf,
            inverse_cdf,
        } = storage;
        let phase = self.instantiate_in(theta, values, cdf)?;
        if sampling == PhaseSampling::Exact || !tabulates(&phase) {
            return Ok(Sampled::Exact(phase));
        }
        let Ok(table) = InverseCdf::new(&phase) else {
            return Ok(Sampled::Exact(phase));
        };
        let table: &'a InverseCdf<F> = inverse_cdf.insert(table);
        Ok(Sampled::Table(TableSampled::new(phase, table)))
    }

    /// [`instantiate`](Self::instantiate) with the storage's fields apart.
    fn instantiate_in<'a, F: Real>(
        &self,
        theta: &'a mut Vec<F>,
        values: &'a mut Vec<F>,
        cdf: &'a mut Vec<F>,
    ) -> Result<Phase<'a, F>> {
        match &self.table {
            None => match Spec::<F>::parse(&self.text).map_err(|e| spec_error(&self.text, e))? {
                Spec::Analytic(p) => Ok(p),
                Spec::Table { .. } => unreachable!("a table spec always has its table"),
            },
            Some((edges, bins)) => {
                *theta = edges.iter().map(|&x| F::from_f64(x)).collect();
                // The last edge is π exactly in the target precision.
                if let Some(last) = theta.last_mut() {
                    *last = F::PI;
                }
                *values = bins.iter().map(|&x| F::from_f64(x)).collect();
                *cdf = vec![F::ZERO; edges.len()];
                let (theta, values): (&'a [F], &'a [F]) = (theta, values);
                let t = Tabulated::new(theta, values, cdf)
                    .map_err(|e| core_error(&format!("phase {}", self.text), e))?;
                Ok(Phase::Tabulated(t))
            }
        }
    }
}

impl fmt::Display for PhaseSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text)
    }
}

fn spec_error(text: &str, e: omnee_core::Error) -> RenderError {
    RenderError::Input(format!(
        "phase \"{}\": {e}; allowed: iso, hg:G, tthg:G1,G2,W, ff:B,N, draine:G,ALPHA, mie:DIAMETER_UM, rayleigh, table:FILE.csv",
        text.trim()
    ))
}

/// Reads `angle_deg,value` lines into bin edges and values.
fn read_table(path: &str) -> Result<(Vec<f64>, Vec<f64>)> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| RenderError::Input(format!("phase table:{path}: cannot read: {e}")))?;
    let mut angles = Vec::new();
    let mut values = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let err =
            |what: &str| RenderError::Input(format!("phase table:{path}, line {}: {what}", i + 1));
        let mut cols = line.split(',').map(str::trim);
        let (a, v) = (cols.next().unwrap_or(""), cols.next().unwrap_or(""));
        if cols.next().is_some() {
            return Err(err(&format!(
                "\"{line}\" has more than 2 columns; allowed: angle_deg,value"
            )));
        }
        let (a, v) = match (a.parse::<f64>(), v.parse::<f64>()) {
            (Ok(a), Ok(v)) => (a, v),
            _ if angles.is_empty() && values.is_empty() && i == first_data_line(&text) => continue, // header
            _ => {
                return Err(err(&format!(
                    "\"{line}\" is not two numbers; allowed: angle_deg,value"
                )));
            }
        };
        let lo = angles.last().copied().unwrap_or(-f64::MIN_POSITIVE);
        if !(a > lo && (0.0..=180.0).contains(&a)) {
            return Err(err(&format!(
                "angle_deg = {a} is out of range; allowed: ({lo}, 180], increasing from 0"
            )));
        }
        // The table is built in f32 as well as f64: a value above f32's
        // range would be infinite there, which is out of range here, not a
        // non-finite value of the file's.
        if !(v >= 0.0 && v <= f64::from(f32::MAX)) {
            return Err(err(&format!(
                "value = {v} is out of range; allowed: [0, {:e}] (the renderer works in f32)",
                f32::MAX
            )));
        }
        angles.push(a);
        values.push(v);
    }
    if angles.is_empty() {
        return Err(RenderError::Input(format!(
            "phase table:{path}: no data lines; allowed: one or more angle_deg,value lines"
        )));
    }
    let rad = |d: f64| d.to_radians();
    let mut edges = vec![0.0];
    for w in angles.windows(2) {
        edges.push(rad(0.5 * (w[0] + w[1])));
    }
    edges.push(std::f64::consts::PI);
    Ok((edges, values))
}

/// The index of the first line that is neither blank nor a comment.
fn first_data_line(text: &str) -> usize {
    text.lines()
        .position(|l| {
            let l = l.trim();
            !l.is_empty() && !l.starts_with('#')
        })
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use omnee_core::phase::PhaseFunction;

    #[test]
    fn analytic_specs_parse_in_both_precisions() {
        for s in [
            "iso",
            "hg:0.9",
            "tthg:0.99,-0.44,0.96",
            "ff:0.0183,1.1",
            "draine:0.5,1",
            "mie:10",
            "rayleigh",
        ] {
            let p = PhaseSpec::parse(s).unwrap();
            let mut t = TableStorage::<f32>::default();
            let f = p.instantiate(&mut t).unwrap();
            assert!(f.mean_cosine().is_finite(), "{s}");
        }
    }

    #[test]
    fn table_sampling_tabulates_the_slow_samplers_only() {
        for (s, tabulated) in [
            ("iso", false),
            ("hg:0.9", false),
            ("tthg:0.99,-0.44,0.96", false),
            ("ff:0.0183,1.1", true),
            ("draine:0.5,1", true),
            ("mie:10", true),
            ("rayleigh", true),
        ] {
            let p = PhaseSpec::parse(s).unwrap();
            let mut t = TableStorage::<f32>::default();
            let table = p.sampled(PhaseSampling::Table, &mut t).unwrap();
            assert_eq!(table.is_tabulated(), tabulated, "{s}");
            assert_eq!(table.samples_exactly(), !tabulated, "{s}");
            let mut e = TableStorage::<f32>::default();
            let exact = p.sampled(PhaseSampling::Exact, &mut e).unwrap();
            assert!(!exact.is_tabulated(), "{s}");
            // The same p either way; the table's draw carries p/q.
            assert_eq!(table.phase(), exact.phase(), "{s}");
            let (d, q, ratio) = table.sample_ratio(0.3);
            assert!((ratio / (table.eval(d) / q) - 1.0).abs() < 1e-5, "{s}");
        }
    }

    #[test]
    fn a_table_with_a_zero_density_node_is_sampled_exactly() {
        // The inverse CDF needs p > 0 at its nodes; this table is 0 on
        // (45°, 135°), where its CDF stays at 1/2, the node u = 64/128, so
        // the renderer falls back to the exact sampler.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("zero.csv");
        std::fs::write(&path, "0,1\n90,0\n180,1\n").unwrap();
        let p = PhaseSpec::parse(&format!("table:{}", path.display())).unwrap();
        let mut t = TableStorage::<f32>::default();
        let f = p.sampled(PhaseSampling::Table, &mut t).unwrap();
        assert!(!f.is_tabulated());
        // A positive table is tabulated.
        let path = dir.path().join("positive.csv");
        std::fs::write(&path, "0,50\n10,5\n90,1\n180,0.5\n").unwrap();
        let p = PhaseSpec::parse(&format!("table:{}", path.display())).unwrap();
        let mut t = TableStorage::<f32>::default();
        assert!(
            p.sampled(PhaseSampling::Table, &mut t)
                .unwrap()
                .is_tabulated()
        );
    }

    #[test]
    fn bad_specs_name_the_parameter() {
        let e = PhaseSpec::parse("hg:1.5").unwrap_err().to_string();
        assert!(e.contains("g = 1.5") && e.contains("(-1, 1)"), "{e}");
        let e = PhaseSpec::parse("blob").unwrap_err().to_string();
        assert!(e.contains("blob") && e.contains("allowed"), "{e}");
    }

    #[test]
    fn a_flat_table_is_isotropic() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("flat.csv");
        std::fs::write(&path, "angle_deg,value\n0,1\n90,1\n180,1\n").unwrap();
        let p = PhaseSpec::parse(&format!("table:{}", path.display())).unwrap();
        let mut t = TableStorage::<f64>::default();
        let f = p.instantiate(&mut t).unwrap();
        assert!(f.mean_cosine().abs() < 1e-12);
        let d = omnee_core::phase::Deflection::from_theta(1.0);
        assert!((f.eval(d) - 0.25 / std::f64::consts::PI).abs() < 1e-12);
    }

    #[test]
    fn a_bad_table_names_its_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.csv");
        std::fs::write(&path, "0,1\n90,-1\n").unwrap();
        let e = PhaseSpec::parse(&format!("table:{}", path.display()))
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 2") && e.contains("value = -1"), "{e}");
    }

    #[test]
    fn a_table_value_beyond_f32_is_out_of_range_not_non_finite() {
        // 1e300 is a finite number, but infinite in f32, where the renderer
        // builds the table too: the file's line says so, with the range.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("huge.csv");
        std::fs::write(
            &path,
            "0,1e300
180,1
",
        )
        .unwrap();
        let e = PhaseSpec::parse(&format!("table:{}", path.display()))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 1: value = 1000000000") && e.contains("allowed: [0, 3.4028235e38]"),
            "{e}"
        );
        // The largest f32 values are accepted: their sum is finite in f64.
        std::fs::write(
            &path,
            "0,3.4e38
180,3.4e38
",
        )
        .unwrap();
        let p = PhaseSpec::parse(&format!("table:{}", path.display())).unwrap();
        let mut t = TableStorage::<f64>::default();
        let f = p.instantiate(&mut t).unwrap();
        let d = omnee_core::phase::Deflection::from_theta(1.0);
        assert!((f.eval(d) - 0.25 / std::f64::consts::PI).abs() < 1e-12);
    }
}
