//! Running sums of a Monte Carlo estimator, for its mean and standard error.

/// `Σx` and `Σx²` of an estimator's samples.
#[derive(Clone, Copy, Debug, Default)]
pub struct Moments {
    sum: f64,
    sum2: f64,
}

impl Moments {
    /// Adds the sample `x`.
    pub fn push(&mut self, x: f64) {
        self.sum += x;
        self.sum2 += x * x;
    }

    /// Adds another run's sums.
    pub fn add(&mut self, o: &Moments) {
        self.sum += o.sum;
        self.sum2 += o.sum2;
    }

    /// `(mean, standard error of the mean)` over `n` samples: the mean
    /// `Σx/n`, the unbiased variance `(Σx² − Σx·mean)/(n − 1)` (clamped at
    /// 0), and `√(variance/n)`.
    pub fn mean_stderr(&self, n: u64) -> (f64, f64) {
        let n = n as f64;
        let mean = self.sum / n;
        let var = ((self.sum2 - self.sum * mean) / (n - 1.0).max(1.0)).max(0.0);
        (mean, (var / n).sqrt())
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
}
