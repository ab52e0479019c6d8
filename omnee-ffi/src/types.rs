//! The C types: plain-old-data structs generic over the precision (cbindgen
//! names each instance `_f32` or `_f64`), and the opaque objects, whose
//! storage sizes are constants checked against the core's types at compile
//! time.

use crate::boundary::{pack, unpack, words};
use core::mem::MaybeUninit;
use omnee_core::bridge::{BridgeSample, VertexCount};
use omnee_core::phase::{Deflection, Phase};
use omnee_core::real::{Real, Vector};
use omnee_core::reference::PointToPoint;
use omnee_core::sampling::{Connection, Sample};

/// A point or direction `(x, y, z)`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct omnee_vec3<F> {
    /// x.
    pub x: F,
    /// y.
    pub y: F,
    /// z.
    pub z: F,
}

impl<F: Real> omnee_vec3<F> {
    /// The core's vector.
    pub(crate) fn get(self) -> F::Vec3 {
        F::Vec3::new(self.x, self.y, self.z)
    }

    /// From the core's vector.
    pub(crate) fn from_core(v: F::Vec3) -> Self {
        let [x, y, z] = v.to_array();
        Self { x, y, z }
    }

    /// Whether every component is finite.
    pub(crate) fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
}

/// A sampled scattering vertex (the core's `Sample`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct omnee_sample<F> {
    /// The vertex x1.
    pub x1: omnee_vec3<F>,
    /// Its density in the volume measure (1/m³), finite, saturating at the
    /// precision's largest number (and 0 where it underflows, e.g. s > 1e13
    /// in f32).
    pub pdf: F,
    /// The estimator k(x1)/pdf(x1) without f_c (1/m), finite and ≥ 0;
    /// multiply by f_c (`omnee_problem_f_c_*`) for one estimate.
    pub weight: F,
}

impl<F: Real> omnee_sample<F> {
    /// From the core's sample.
    pub(crate) fn from_core(s: Sample<F>) -> Self {
        Self {
            x1: omnee_vec3::from_core(s.x1),
            pdf: s.pdf,
            weight: s.weight,
        }
    }

    /// The core's sample.
    pub(crate) fn get(self) -> Sample<F> {
        Sample {
            x1: self.x1.get(),
            pdf: self.pdf,
            weight: self.weight,
        }
    }
}

/// A deflection angle θ ∈ [0, π] in cancellation-free form (the core's
/// `Deflection`): `one_minus_cos = 1 − cos θ`, `one_plus_cos = 1 + cos θ`,
/// each accurate where it is small. Make one with `omnee_deflection_*`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct omnee_deflection<F> {
    /// θ in radians, in [0, π].
    pub theta: F,
    /// 1 − cos θ, in [0, 2].
    pub one_minus_cos: F,
    /// 1 + cos θ, in [0, 2].
    pub one_plus_cos: F,
}

impl<F: Real> omnee_deflection<F> {
    /// From the core's deflection.
    pub(crate) fn from_core(d: Deflection<F>) -> Self {
        Self {
            theta: d.theta,
            one_minus_cos: d.one_minus_cos,
            one_plus_cos: d.one_plus_cos,
        }
    }

    /// The core's deflection.
    pub(crate) fn get(self) -> Deflection<F> {
        Deflection {
            theta: self.theta,
            one_minus_cos: self.one_minus_cos,
            one_plus_cos: self.one_plus_cos,
        }
    }
}

/// `omnee_rays.directions`: uniform on the sphere, pdf 1/(4π).
pub const OMNEE_DIRECTIONS_SPHERE: u32 = 0;
/// `omnee_rays.directions`: cosine-weighted about `omnee_rays.normal`.
pub const OMNEE_DIRECTIONS_COSINE: u32 = 1;
/// `omnee_rays.region`: the medium fills all of space.
pub const OMNEE_REGION_EVERYWHERE: u32 = 0;
/// `omnee_rays.region`: the medium fills the slab `z_min ≤ z ≤ z_max`.
pub const OMNEE_REGION_SLAB: u32 = 1;

/// How the ray techniques (equiangular, distance, and the MIS companion)
/// draw a ray from x2, and where the medium is along it. All zero (the
/// default): uniform directions, medium everywhere.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct omnee_rays<F> {
    /// `OMNEE_DIRECTIONS_SPHERE` or `OMNEE_DIRECTIONS_COSINE`.
    pub directions: u32,
    /// The cosine's normal at x2, normalised by the library: any finite,
    /// non-zero length (`OMNEE_ERROR_NOT_FINITE` for a NaN or infinite
    /// component, `OMNEE_ERROR_DEGENERATE` for zero); ignored for the
    /// sphere.
    pub normal: omnee_vec3<F>,
    /// `OMNEE_REGION_EVERYWHERE` or `OMNEE_REGION_SLAB`.
    pub region: u32,
    /// The slab's lower plane (finite); ignored for everywhere.
    pub z_min: F,
    /// The slab's upper plane (finite, > z_min); ignored for everywhere.
    pub z_max: F,
}

/// The vertices of one MIS estimate (`omnee_mis_sample_*`): OMNEE's, and
/// now and then the companion's. Sum `f_c · weight` over the present ones.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct omnee_draw<F> {
    /// `vertices[0]` is OMNEE's vertex, `vertices[1]` the companion's; an
    /// absent vertex is all zero.
    pub vertices: [omnee_sample<F>; 2],
    /// Bit `k` is set when `vertices[k]` is present.
    pub present: u32,
}

/// The uniform numbers of a batch (`omnee_omnee_sample_batch_f32`), one
/// array per coordinate, each `len` long.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct omnee_uniforms_f32 {
    /// u0, which draws θ.
    pub u0: *const f32,
    /// u1 = β/θ.
    pub u1: *const f32,
    /// u2 = φ/2π.
    pub u2: *const f32,
    /// The number of entries in each array.
    pub len: usize,
}

/// The vertices of a batch: x1 by coordinate, its pdf and weight (0 where
/// there is no sample), each array `len` long.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct omnee_vertices_f32 {
    /// x coordinates of x1.
    pub x: *mut f32,
    /// y coordinates of x1.
    pub y: *mut f32,
    /// z coordinates of x1.
    pub z: *mut f32,
    /// Volume densities.
    pub pdf: *mut f32,
    /// Weights θ/(s sin θ).
    pub weight: *mut f32,
    /// The number of entries in each array.
    pub len: usize,
}

/// One bridge drawn by `omnee_bridge_sample_*` (the core's `BridgeSample`); its
/// `k` inner vertices are in the caller's array.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct omnee_bridge<F> {
    /// The number of inner vertices k, in [1, OMNEE_MAX_VERTICES].
    pub k: usize,
    /// The path's total length D = d_1 + … + d_{k+1} (m).
    pub length: F,
    /// The density in the product of volume measures (1/m^{3k}),
    /// s³ k! Π q(θ_i) / (Π d_j² D^{k+1}); finite (saturating).
    pub pdf: F,
    /// Π p(θ_i)/q(θ_i): 1 for phase functions that sample exactly.
    pub phase_ratio: F,
    /// The kernel Π p(θ_i) / Π d_j² over pdf, (p/q) D^{k+1}/(s³ k!);
    /// finite and ≥ 0 (saturating). `omnee_bridge_estimate_*` multiplies in
    /// σs^k e^{−σt D} without forming the huge factors alone.
    pub weight: F,
}

impl<F: Real> omnee_bridge<F> {
    /// From the core's sample.
    pub(crate) fn from_core(s: BridgeSample<F>) -> Self {
        Self {
            k: s.k,
            length: s.length,
            pdf: s.pdf,
            phase_ratio: s.phase_ratio,
            weight: s.weight,
        }
    }

    /// The core's sample.
    pub(crate) fn get(self) -> BridgeSample<F> {
        BridgeSample {
            k: self.k,
            length: self.length,
            pdf: self.pdf,
            phase_ratio: self.phase_ratio,
            weight: self.weight,
        }
    }
}

/// A number of bridge vertices drawn by `omnee_vertex_count_sample_*`: `k`
/// and the probability P(k) with which it was drawn.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct omnee_vertex_draw<F> {
    /// The number of inner vertices k.
    pub k: usize,
    /// P(k), in (0, 1].
    pub probability: F,
}

/// A part of a string: `length` bytes from byte `offset`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct omnee_span {
    /// Offset of the first byte.
    pub offset: usize,
    /// Number of bytes.
    pub length: usize,
}

/// An opaque object of the C API: a tag that its constructor sets, and the
/// core's value in fixed-size storage.
///
/// The tag is the type's magic number XOR a checksum of every storage word
/// ([`checksum`]), so an object is accepted only if its storage holds, bit
/// for bit, what a constructor of this type wrote: zeroed memory, a failed
/// constructor's output, the other precision's object, and garbage or
/// altered storage under a copied tag all fail with
/// `OMNEE_ERROR_UNINITIALISED` (a random change passes with probability
/// 2⁻⁶⁴) before any byte of the storage is interpreted, so no pointer a
/// corrupted table object seems to hold is ever followed.
pub(crate) trait Object: Sized + Default {
    /// The core's value.
    type Value: Copy;
    /// The name in error messages.
    const NAME: &'static str;
    /// The object from its value, tagged.
    fn new(value: Self::Value) -> Self;
    /// The value, if a constructor of this type made the object and its
    /// storage is unchanged since.
    fn value(&self) -> Option<&Self::Value>;
}

/// A checksum of an object's storage words: each word times its own odd
/// constant, summed (independent products, so it costs about one cycle a
/// word), then SplitMix64's finaliser ([`omnee_core::rng::mix`]), so that
/// every bit of every word reaches every bit of the result. Any change of a
/// single word changes the sum (the constants are odd), and random words
/// match a given checksum with probability 2⁻⁶⁴.
#[inline]
pub(crate) fn checksum<const N: usize>(words: &[u64; N]) -> u64 {
    let mut h = 0u64;
    let mut k = omnee_core::rng::SplitMix64::GAMMA;
    for &w in words {
        h = h.wrapping_add(w.wrapping_mul(k | 1));
        k = k.wrapping_add(0x6a09_e667_f3bc_c909);
    }
    omnee_core::rng::mix(h)
}

/// Declares the `Object` impl of an opaque struct with fields `tag` and
/// `storage: MaybeUninit<[u64; $words]>` holding a `$value`.
macro_rules! object {
    ($name:ident, $value:ty, $words:ident, $tag:literal, $field:literal) => {
        impl Default for $name {
            /// Untagged and zero: every use reports `OMNEE_ERROR_UNINITIALISED`.
            fn default() -> Self {
                Self {
                    tag: 0,
                    storage: MaybeUninit::zeroed(),
                }
            }
        }

        impl Object for $name {
            type Value = $value;
            const NAME: &'static str = $field;

            #[inline]
            fn new(value: $value) -> Self {
                let storage = pack::<$value, $words>(value);
                Self {
                    tag: u64::from_le_bytes(*$tag) ^ checksum(&words(&storage)),
                    storage,
                }
            }

            #[inline]
            fn value(&self) -> Option<&$value> {
                if self.tag != u64::from_le_bytes(*$tag) ^ checksum(&words(&self.storage)) {
                    return None;
                }
                // SAFETY: the tag matches the checksum of the storage as it
                // is now, which only `new` produces (up to a 2⁻⁶⁴ chance for
                // other bits): the storage holds the `$value` that `new`
                // packed, or a byte copy of it.
                Some(unsafe { unpack::<$value, $words>(&self.storage) })
            }
        }
    };
}

/// 64-bit words of storage in `omnee_connection_f32`.
pub const OMNEE_CONNECTION_F32_WORDS: usize = 11;
/// 64-bit words of storage in `omnee_connection_f64`.
pub const OMNEE_CONNECTION_F64_WORDS: usize = 21;
/// 64-bit words of storage in `omnee_phase_f32`.
pub const OMNEE_PHASE_F32_WORDS: usize = 8;
/// 64-bit words of storage in `omnee_phase_f64`.
pub const OMNEE_PHASE_F64_WORDS: usize = 10;
/// 64-bit words of storage in `omnee_problem_f32`.
pub const OMNEE_PROBLEM_F32_WORDS: usize = 14;
/// 64-bit words of storage in `omnee_problem_f64`.
pub const OMNEE_PROBLEM_F64_WORDS: usize = 27;
/// 64-bit words of storage in `omnee_vertex_count_f32`.
pub const OMNEE_VERTEX_COUNT_F32_WORDS: usize = 18;
/// 64-bit words of storage in `omnee_vertex_count_f64`.
pub const OMNEE_VERTEX_COUNT_F64_WORDS: usize = 34;

// The constants above are the core's sizes on 64-bit targets, rounded up to
// whole words (32-bit targets need at most as much; `pack` checks every
// target at compile time). When the core changes a size, this fails with
// "expected an array with a size of OLD, found one with a size of NEW": set
// the constant to NEW and regenerate the header (omnee-ffi/ci.sh).
/// cbindgen:ignore
#[cfg(target_pointer_width = "64")]
const _: () = {
    use core::mem::size_of;
    const fn words(bytes: usize) -> usize {
        bytes.div_ceil(8)
    }
    let _: [(); OMNEE_CONNECTION_F32_WORDS] = [(); words(size_of::<Connection<f32>>())];
    let _: [(); OMNEE_CONNECTION_F64_WORDS] = [(); words(size_of::<Connection<f64>>())];
    let _: [(); OMNEE_PHASE_F32_WORDS] = [(); words(size_of::<Phase<'static, f32>>())];
    let _: [(); OMNEE_PHASE_F64_WORDS] = [(); words(size_of::<Phase<'static, f64>>())];
    let _: [(); OMNEE_PROBLEM_F32_WORDS] = [(); words(size_of::<PointToPoint<f32>>())];
    let _: [(); OMNEE_PROBLEM_F64_WORDS] = [(); words(size_of::<PointToPoint<f64>>())];
    let _: [(); OMNEE_VERTEX_COUNT_F32_WORDS] = [(); words(size_of::<VertexCount<f32>>())];
    let _: [(); OMNEE_VERTEX_COUNT_F64_WORDS] = [(); words(size_of::<VertexCount<f64>>())];
};

/// The end points x0, x2 and the restriction θ < θmax (opaque; make it with
/// `omnee_connection_init_f32`; copy it freely).
#[repr(C)]
pub struct omnee_connection_f32 {
    tag: u64,
    storage: MaybeUninit<[u64; OMNEE_CONNECTION_F32_WORDS]>,
}
object!(
    omnee_connection_f32,
    Connection<f32>,
    OMNEE_CONNECTION_F32_WORDS,
    b"omCon32\0",
    "connection"
);

/// The end points x0, x2 and the restriction θ < θmax (opaque; make it with
/// `omnee_connection_init_f64`; copy it freely).
#[repr(C)]
pub struct omnee_connection_f64 {
    tag: u64,
    storage: MaybeUninit<[u64; OMNEE_CONNECTION_F64_WORDS]>,
}
object!(
    omnee_connection_f64,
    Connection<f64>,
    OMNEE_CONNECTION_F64_WORDS,
    b"omCon64\0",
    "connection"
);

/// A phase function (opaque; make it with an `omnee_phase_*_f32`
/// constructor; copy it freely). A table's phase function refers to the
/// caller's arrays.
#[repr(C)]
pub struct omnee_phase_f32 {
    tag: u64,
    storage: MaybeUninit<[u64; OMNEE_PHASE_F32_WORDS]>,
}
object!(
    omnee_phase_f32,
    Phase<'static, f32>,
    OMNEE_PHASE_F32_WORDS,
    b"omPhs32\0",
    "phase"
);

/// A phase function (opaque; make it with an `omnee_phase_*_f64`
/// constructor; copy it freely). A table's phase function refers to the
/// caller's arrays.
#[repr(C)]
pub struct omnee_phase_f64 {
    tag: u64,
    storage: MaybeUninit<[u64; OMNEE_PHASE_F64_WORDS]>,
}
object!(
    omnee_phase_f64,
    Phase<'static, f64>,
    OMNEE_PHASE_F64_WORDS,
    b"omPhs64\0",
    "phase"
);

/// The point-to-point problem: a connection in a homogeneous medium, with
/// an optional receiver cosine (opaque; make it with
/// `omnee_problem_init_f32`; copy it freely).
#[repr(C)]
pub struct omnee_problem_f32 {
    tag: u64,
    storage: MaybeUninit<[u64; OMNEE_PROBLEM_F32_WORDS]>,
}
object!(
    omnee_problem_f32,
    PointToPoint<f32>,
    OMNEE_PROBLEM_F32_WORDS,
    b"omPtp32\0",
    "problem"
);

/// The point-to-point problem: a connection in a homogeneous medium, with
/// an optional receiver cosine (opaque; make it with
/// `omnee_problem_init_f64`; copy it freely).
#[repr(C)]
pub struct omnee_problem_f64 {
    tag: u64,
    storage: MaybeUninit<[u64; OMNEE_PROBLEM_F64_WORDS]>,
}
object!(
    omnee_problem_f64,
    PointToPoint<f64>,
    OMNEE_PROBLEM_F64_WORDS,
    b"omPtp64\0",
    "problem"
);

/// The distribution of the number of bridge vertices k ∈ [1, k_max]
/// (opaque; make it with `omnee_vertex_count_init_f32`; copy it freely).
#[repr(C)]
pub struct omnee_vertex_count_f32 {
    tag: u64,
    storage: MaybeUninit<[u64; OMNEE_VERTEX_COUNT_F32_WORDS]>,
}
object!(
    omnee_vertex_count_f32,
    VertexCount<f32>,
    OMNEE_VERTEX_COUNT_F32_WORDS,
    b"omVtc32\0",
    "count"
);

/// The distribution of the number of bridge vertices k ∈ [1, k_max]
/// (opaque; make it with `omnee_vertex_count_init_f64`; copy it freely).
#[repr(C)]
pub struct omnee_vertex_count_f64 {
    tag: u64,
    storage: MaybeUninit<[u64; OMNEE_VERTEX_COUNT_F64_WORDS]>,
}
object!(
    omnee_vertex_count_f64,
    VertexCount<f64>,
    OMNEE_VERTEX_COUNT_F64_WORDS,
    b"omVtc64\0",
    "count"
);

/// The precisions of the C API and their opaque types.
pub(crate) trait Precision: Real {
    /// `omnee_connection_*`.
    type Connection: Object<Value = Connection<Self>>;
    /// `omnee_phase_*`.
    type Phase: Object<Value = Phase<'static, Self>>;
    /// `omnee_problem_*`.
    type Problem: Object<Value = PointToPoint<Self>>;
    /// `omnee_vertex_count_*`.
    type VertexCount: Object<Value = VertexCount<Self>>;
}

impl Precision for f32 {
    type Connection = omnee_connection_f32;
    type Phase = omnee_phase_f32;
    type Problem = omnee_problem_f32;
    type VertexCount = omnee_vertex_count_f32;
}

impl Precision for f64 {
    type Connection = omnee_connection_f64;
    type Phase = omnee_phase_f64;
    type Problem = omnee_problem_f64;
    type VertexCount = omnee_vertex_count_f64;
}
