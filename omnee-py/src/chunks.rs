//! The parallel loops: the items of a call (draws, points, elements) cut
//! into chunks of [`CHUNK`] items, each chunk of every input and output
//! array handed to one task of rayon's pool, so that the outputs are
//! written in place, with no per-item allocation and no gather afterwards.

use rayon::prelude::*;

/// Items per task. A call with at most this many items runs on the calling
/// thread (a task handed to the pool costs microseconds).
pub const CHUNK: usize = 4096;

/// Arrays that split at an item boundary.
pub trait Split: Sized + Send {
    /// The number of items.
    fn items(&self) -> usize;
    /// The first `mid` items and the rest.
    fn split_at(self, mid: usize) -> (Self, Self);
}

/// A slice whose items are `k` consecutive elements (a point: 3, a draw's
/// uniform numbers: 3 or 6, a scalar: 1).
pub struct Items<S> {
    /// The elements.
    pub data: S,
    /// Elements per item.
    pub k: usize,
}

impl<T: Sync> Split for Items<&[T]> {
    fn items(&self) -> usize {
        self.data.len() / self.k
    }
    fn split_at(self, mid: usize) -> (Self, Self) {
        let (a, b) = self.data.split_at(mid * self.k);
        let k = self.k;
        (Items { data: a, k }, Items { data: b, k })
    }
}

impl<T: Send> Split for Items<&mut [T]> {
    fn items(&self) -> usize {
        self.data.len() / self.k
    }
    fn split_at(self, mid: usize) -> (Self, Self) {
        let (a, b) = self.data.split_at_mut(mid * self.k);
        let k = self.k;
        (Items { data: a, k }, Items { data: b, k })
    }
}

impl Split for std::ops::Range<usize> {
    fn items(&self) -> usize {
        self.len()
    }
    fn split_at(self, mid: usize) -> (Self, Self) {
        (self.start..self.start + mid, self.start + mid..self.end)
    }
}

/// Tuples of arrays with the same number of items split together.
macro_rules! split_tuple {
    ($($name:ident),+) => {
        #[allow(non_snake_case)]
        impl<A: Split, $($name: Split),+> Split for (A, $($name),+) {
            fn items(&self) -> usize {
                self.0.items()
            }
            fn split_at(self, mid: usize) -> (Self, Self) {
                let (A, $($name),+) = self;
                let a = A.split_at(mid);
                $(let $name = $name.split_at(mid);)+
                ((a.0, $($name.0),+), (a.1, $($name.1),+))
            }
        }
    };
}

split_tuple!(B);
split_tuple!(B, C);
split_tuple!(B, C, D);
split_tuple!(B, C, D, E);

/// Runs `f(start, chunk)` over consecutive chunks of `all`, `start` being
/// the chunk's first item; in parallel when there is more than one chunk.
/// Returns the error of the first chunk (in item order) that fails.
pub fn run<S: Split, E: Send>(
    all: S,
    f: impl Fn(usize, S) -> Result<(), E> + Sync,
) -> Result<(), E> {
    let n = all.items();
    if n <= CHUNK {
        return f(0, all);
    }
    let mut parts = Vec::with_capacity(n.div_ceil(CHUNK));
    let (mut rest, mut start) = (all, 0);
    while rest.items() > CHUNK {
        let (head, tail) = rest.split_at(CHUNK);
        parts.push((start, head));
        (rest, start) = (tail, start + CHUNK);
    }
    parts.push((start, rest));
    parts
        .into_par_iter()
        .map(|(start, part)| f(start, part))
        .find_first(Result::is_err)
        .unwrap_or(Ok(()))
}
