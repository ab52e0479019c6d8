//! Work on a rayon pool: the `--threads` option, and samples in chunks of
//! [`CHUNK`] so that results depend on the seed and the sample count, never
//! on the thread count.

use crate::error::{CliError, Result};
use rayon::prelude::*;

/// Samples per chunk of `probe` and `estimate` (one random stream each).
pub const CHUNK: u64 = 4096;

/// Runs `f` on a rayon pool of `threads` workers (0: one per core).
pub fn with_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> Result<T> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| CliError::Input(format!("--threads = {threads}: {e}")))?;
    Ok(pool.install(f))
}

/// The chunks of `samples` samples: `(chunk index k, samples in it)`, every
/// chunk [`CHUNK`] long but the last.
pub fn chunks(samples: u64) -> impl Iterator<Item = (u64, u64)> {
    (0..samples.div_ceil(CHUNK)).map(move |k| (k, CHUNK.min(samples - k * CHUNK)))
}

/// Runs `f(chunk index, samples in chunk)` over all [`chunks`] in parallel
/// and returns the results in chunk order.
pub fn chunked<T: Send>(samples: u64, f: impl Fn(u64, u64) -> T + Sync) -> Vec<T> {
    chunks(samples)
        .collect::<Vec<_>>()
        .into_par_iter()
        .map(|(k, n)| f(k, n))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_cover_the_samples_in_order() {
        let c: Vec<_> = chunks(2 * CHUNK + 5).collect();
        assert_eq!(c, [(0, CHUNK), (1, CHUNK), (2, 5)]);
        assert_eq!(chunks(CHUNK).count(), 1);
        assert_eq!(chunked(CHUNK + 1, |k, n| (k, n)), [(0, CHUNK), (1, 1)]);
    }
}
