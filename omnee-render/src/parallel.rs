//! Work on a rayon pool, the one way the library runs in parallel: items
//! mapped on the pool with their results kept in item order, and samples in
//! chunks of [`CHUNK`] (one random stream each), so that results depend on
//! the seed and the sample count, never on the thread count; both stop early
//! when the caller cancels.

use crate::error::{RenderError, Result};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// Samples per chunk of a Monte Carlo estimate, and light paths per chunk
/// of a splatting render: one random stream each.
pub const CHUNK: u64 = 4096;

/// Runs `f` on a rayon pool of `threads` workers (0: one per core).
pub fn with_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> Result<T> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| RenderError::Input(format!("threads = {threads}: {e}")))?;
    Ok(pool.install(f))
}

/// `f(0), …, f(items − 1)` computed on the current pool, in item order;
/// `None` if `cancel` was set before all of them started (each checks it
/// before it starts).
pub fn map_items<T: Send>(
    items: u64,
    cancel: &AtomicBool,
    f: impl Fn(u64) -> T + Sync,
) -> Option<Vec<T>> {
    map_items_with(items, cancel, || (), |(), k| f(k))
}

/// [`map_items`] with scratch space: `f(&mut scratch, k)`, the scratch made
/// by `init` once per piece of work a thread takes (rayon's `map_init`), so
/// that items reuse their buffers. What an item computes must not depend on
/// what the scratch held before.
pub fn map_items_with<T: Send, S>(
    items: u64,
    cancel: &AtomicBool,
    init: impl Fn() -> S + Sync + Send,
    f: impl Fn(&mut S, u64) -> T + Sync,
) -> Option<Vec<T>> {
    (0..items)
        .into_par_iter()
        .map_init(init, |scratch, k| {
            (!cancel.load(Ordering::Relaxed)).then(|| f(scratch, k))
        })
        .collect()
}

/// The chunks of `samples` samples: `(chunk index k, samples in it)`, every
/// chunk [`CHUNK`] long but the last.
pub fn chunks(samples: u64) -> impl Iterator<Item = (u64, u64)> {
    (0..samples.div_ceil(CHUNK)).map(move |k| (k, CHUNK.min(samples - k * CHUNK)))
}

/// Runs `f(chunk index, samples in chunk)` over all [`chunks`] on the
/// current pool and returns the results in chunk order;
/// [`RenderError::Cancelled`] if `cancel` was set before the last chunk
/// started.
pub fn chunked<T: Send>(
    samples: u64,
    cancel: &AtomicBool,
    f: impl Fn(u64, u64) -> T + Sync,
) -> Result<Vec<T>> {
    map_items(samples.div_ceil(CHUNK), cancel, |k| {
        f(k, CHUNK.min(samples - k * CHUNK))
    })
    .ok_or(RenderError::Cancelled)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_cover_the_samples_in_order() {
        let go = AtomicBool::new(false);
        let c: Vec<_> = chunks(2 * CHUNK + 5).collect();
        assert_eq!(c, [(0, CHUNK), (1, CHUNK), (2, 5)]);
        assert_eq!(chunks(CHUNK).count(), 1);
        assert_eq!(
            chunked(CHUNK + 1, &go, |k, n| (k, n)).unwrap(),
            [(0, CHUNK), (1, 1)]
        );
        assert_eq!(map_items(3, &go, |k| 2 * k), Some(vec![0, 2, 4]));
    }

    #[test]
    fn a_cancelled_map_returns_nothing() {
        let stop = AtomicBool::new(true);
        assert_eq!(map_items(3, &stop, |k| k), None);
        assert!(matches!(
            chunked(10, &stop, |k, _| k),
            Err(RenderError::Cancelled)
        ));
    }
}
