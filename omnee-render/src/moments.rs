//! Running sums of a Monte Carlo estimator, for its mean and standard error.

/// `Σx` and `Σx²` of an estimator's samples, the squares kept relative to
/// a power of two `c ≥ max |x|` (`Σx² = c² · Σ(x/c)²`), so that they neither
/// underflow for tiny samples (a transfer of 1e-260 would square to 0) nor
/// overflow for huge ones. Scaling by a power of two is exact: where `x²`
/// itself neither underflows nor overflows, the sums are those of the plain
/// formula bit for bit.
#[derive(Clone, Copy, Debug, Default)]
pub struct Moments {
    sum: f64,
    /// `Σ(x/c)²`.
    sum2: f64,
    /// `c`, a power of two (0 before the first non-zero sample).
    scale: f64,
}

/// The smallest power of two `≥ |x|` for a finite non-zero `x` (the next
/// one up for powers of two themselves: `2^(⌊log2 |x|⌋ + 1)`).
fn power_of_two_above(x: f64) -> f64 {
    let exponent = ((x.abs().to_bits() >> 52) & 0x7ff) as i32;
    // Subnormals have exponent field 0 and are below 2^-1022.
    let e = if exponent == 0 {
        -1022
    } else {
        exponent - 1022
    };
    if e > 1023 {
        f64::MAX
    } else if e >= -1022 {
        f64::from_bits(((e + 1023) as u64) << 52)
    } else {
        f64::MIN_POSITIVE
    }
}

impl Moments {
    /// Adds the sample `x`.
    pub fn push(&mut self, x: f64) {
        self.sum += x;
        if x != 0.0 && x.is_finite() && x.abs() >= self.scale {
            self.rescale(power_of_two_above(x));
        }
        let y = if self.scale > 0.0 { x / self.scale } else { x };
        self.sum2 += y * y;
    }

    /// Moves the squares to the scale `c` (≥ the current one).
    fn rescale(&mut self, c: f64) {
        if self.scale > 0.0 {
            let r = self.scale / c;
            self.sum2 *= r * r;
        }
        self.scale = c;
    }

    /// Adds another run's sums.
    pub fn add(&mut self, o: &Moments) {
        self.sum += o.sum;
        let mut o = *o;
        if o.scale > self.scale {
            self.rescale(o.scale);
        } else if o.scale > 0.0 {
            o.rescale(self.scale);
        }
        self.sum2 += o.sum2;
    }

    /// `(mean, standard error of the mean)` over `n` samples: the mean
    /// `Σx/n`, the unbiased variance `(Σx² − Σx·mean)/(n − 1)` (clamped at
    /// 0), and `√(variance/n)`, all relative to the scale `c`.
    pub fn mean_stderr(&self, n: u64) -> (f64, f64) {
        let n = n as f64;
        let mean = self.sum / n;
        let c = if self.scale > 0.0 { self.scale } else { 1.0 };
        let (sum, m) = (self.sum / c, mean / c);
        let var = ((self.sum2 - sum * m) / (n - 1.0).max(1.0)).max(0.0);
        (mean, c * (var / n).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mean_and_standard_error_of_a_small_sample() {
        let mut m = Moments::default();
        for x in [1.0, 2.0, 3.0, 4.0] {
            m.push(x);
        }
        let (mean, se) = m.mean_stderr(4);
        assert_eq!(mean, 2.5);
        // Variance 5/3, standard error √(5/12).
        assert!((se - (5.0f64 / 12.0).sqrt()).abs() < 1e-15);
    }

    #[test]
    fn tiny_and_huge_samples_keep_their_standard_error() {
        for scale in [1e-300, 1e-200, 1.0, 1e200, 1e300] {
            let mut a = Moments::default();
            let mut b = Moments::default();
            for x in [1.0, 2.0, 3.0, 4.0] {
                a.push(x * scale);
            }
            b.push(0.0);
            b.add(&a);
            let (mean, se) = a.mean_stderr(4);
            assert!((mean / scale - 2.5).abs() < 1e-12, "{scale}: {mean}");
            let want = (5.0f64 / 12.0).sqrt() * scale;
            assert!((se / want - 1.0).abs() < 1e-12, "{scale}: {se} vs {want}");
            // A zero sample joins at the other's scale: five samples now.
            let (_, se5) = b.mean_stderr(5);
            assert!(se5 > 0.0 && se5.is_finite(), "{scale}: {se5}");
        }
    }

    #[test]
    fn the_sums_are_the_plain_formulas_where_squares_fit() {
        let xs = [0.3, 1.7e-3, 12.5, 0.0, 7.25, 1e-5];
        let (mut m, mut sum, mut sum2) = (Moments::default(), 0.0, 0.0);
        for x in xs {
            m.push(x);
            sum += x;
            sum2 += x * x;
        }
        let n = xs.len() as f64;
        let mean = sum / n;
        let se = ((sum2 - sum * mean) / (n - 1.0) / n).sqrt();
        assert_eq!(m.mean_stderr(6), (mean, se));
    }
}
