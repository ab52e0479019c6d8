//! The statistics of the tests: the regularized incomplete gamma function,
//! χ² and normal tails, Šidák's family correction and Pearson's χ² with the
//! pooling of Mitsuba 3's and pbrt-v4's harnesses (docs/math.md §5.6).

/// ln Γ(x) for x > 0 (Lanczos, g = 7, 9 terms; relative error ~1e-15).
pub fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        let pi = core::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let t = x + 7.5;
    let mut a = C[0];
    for (i, &c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * core::f64::consts::TAU.ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The regularized upper incomplete gamma function `Q(a, x) = Γ(a, x)/Γ(a)`:
/// the series for `P = 1 − Q` below `x = a + 1`, Lentz's continued fraction
/// above (Numerical Recipes §6.2, as Cephes' `igamc` that both reference
/// harnesses port).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let prefactor = (-x + a * x.ln() - ln_gamma(a)).exp();
    if x < a + 1.0 {
        let (mut ap, mut term) = (a, 1.0 / a);
        let mut sum = term;
        for _ in 0..100_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-17 {
                break;
            }
        }
        1.0 - sum * prefactor
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..100_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        prefactor * h
    }
}

/// `P(X > x)` for X ~ χ² with `dof` degrees of freedom.
pub fn chi2_sf(x: f64, dof: usize) -> f64 {
    gamma_q(0.5 * dof as f64, 0.5 * x)
}

/// The two-sided normal tail `P(|Z| > z) = Q(1/2, z²/2)`.
pub fn normal_two_sided_tail(z: f64) -> f64 {
    gamma_q(0.5, 0.5 * z * z)
}

/// The z with `P(|Z| > z) = p` (bisection; p in (1e-300, 1)).
pub fn normal_two_sided_quantile(p: f64) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 40.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if normal_two_sided_tail(mid) > p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Šidák's per-test level for a family of `tests` tests at family level `alpha`:
/// `1 − (1 − α)^{1/tests}`.
pub fn sidak(alpha: f64, tests: usize) -> f64 {
    -((1.0 - alpha).ln() / tests as f64).exp_m1()
}

/// The result of [`chi2`].
#[derive(Clone, Debug)]
pub struct Chi2 {
    pub statistic: f64,
    pub dof: usize,
    pub p_value: f64,
    /// The five unpooled cells with the largest contributions, as
    /// `(cell, observed, expected)`, for the failure message.
    pub worst: Vec<(usize, f64, f64)>,
}

/// Pearson's χ² over cells with observed and expected counts, pooled as in
/// Mitsuba 3 / pbrt-v4: cells sorted by expected count, those below 5 merged
/// into pools of at least 5; dof = pooled cells − 1. Rejects outright (Err) a
/// negative expected count beyond `tolerance` (the quadrature error of a
/// count computed as `N − Σ expected`: a density that integrates to more
/// than 1) and observations in a cell whose expected count is not
/// positive (samples where the pdf says none can be).
pub fn chi2(observed: &[f64], expected: &[f64], tolerance: f64) -> Result<Chi2, String> {
    let mut cells: Vec<(usize, f64, f64)> = Vec::with_capacity(observed.len());
    for (i, (&o, &e)) in observed.iter().zip(expected).enumerate() {
        if !e.is_finite() || e < -tolerance {
            return Err(format!("cell {i}: expected count {e} (observed {o})"));
        }
        if e <= 0.0 && o == 0.0 {
            continue; // e.g. "no sample" for a sampler that always returns one
        }
        if e <= 0.0 {
            return Err(format!(
                "cell {i}: {o} samples where the pdf integrates to {e}"
            ));
        }
        cells.push((i, o, e));
    }
    let mut worst: Vec<(usize, f64, f64)> = cells.iter().copied().filter(|c| c.2 >= 5.0).collect();
    worst.sort_by(|a, b| ((b.1 - b.2).powi(2) / b.2).total_cmp(&((a.1 - a.2).powi(2) / a.2)));
    worst.truncate(5);
    cells.sort_by(|a, b| a.2.total_cmp(&b.2));
    let (mut statistic, mut n) = (0.0, 0usize);
    let (mut po, mut pe) = (0.0, 0.0);
    for (_, o, e) in cells {
        po += o;
        pe += e;
        if pe >= 5.0 {
            statistic += (po - pe) * (po - pe) / pe;
            n += 1;
            po = 0.0;
            pe = 0.0;
        }
    }
    if pe > 0.0 {
        statistic += (po - pe) * (po - pe) / pe;
        n += 1;
    }
    if n < 2 {
        return Err(format!("only {n} cells after pooling"));
    }
    let dof = n - 1;
    Ok(Chi2 {
        statistic,
        dof,
        p_value: chi2_sf(statistic, dof),
        worst,
    })
}

#[test]
fn incomplete_gamma_matches_tabulated_chi2_quantiles() {
    // Quantiles from standard tables (Abramowitz & Stegun 26.4, and the
    // closed forms for dof 1 and 2).
    let cases = [
        (3.841_458_820_694_124, 1, 0.05),
        (1.0, 1, 0.317_310_507_862_914_15), // erfc(1/√2)
        (6.634_896_601_021_214, 1, 0.01),
        (18.307_038_053_275_146, 10, 0.05),
        (23.209_251_158_954_356, 10, 0.01),
        (0.114_831_801_899_117_9, 3, 0.99),
    ];
    for (x, dof, p) in cases {
        let got = chi2_sf(x, dof);
        assert!(
            (got - p).abs() < 1e-9 * p.max(1e-3) + 1e-12,
            "χ²({dof}) sf({x}) = {got}, want {p}"
        );
    }
    for &x in &[0.1, 1.0, 5.0, 40.0] {
        assert!((chi2_sf(x, 2) - (-0.5 * x).exp()).abs() < 1e-14);
    }
    let z = normal_two_sided_quantile(0.05);
    assert!((z - 1.959_963_984_540_054).abs() < 1e-9, "{z}");
}

#[test]
fn chi2_rejects_impossible_cells_and_accepts_exact_counts() {
    assert!(chi2(&[3.0, 10.0, 10.0], &[0.0, 11.5, 11.5], 1e-9).is_err());
    assert!(chi2(&[10.0, 10.0], &[-5.0, 25.0], 1e-9).is_err());
    let r = chi2(&[100.0, 200.0, 50.0], &[100.0, 200.0, 50.0], 1e-9).unwrap();
    assert!(r.statistic == 0.0 && r.dof == 2 && r.p_value == 1.0);
    let r = chi2(&[150.0, 150.0, 50.0], &[100.0, 200.0, 50.0], 1e-9).unwrap();
    assert!(r.p_value < 1e-6, "{r:?}");
}
