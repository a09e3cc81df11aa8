//! Four f64 lanes, for the contact solver's inner loop.
//!
//! glam's f64 vectors compute one component at a time. A contact point's work comes in
//! threes instead: the speeds along its normal and two tangents, and the three components of
//! an impulse. `F64x4` holds such a triple (the fourth lane is padding), and the solver does
//! each operation on all lanes at once.
//!
//! Every lane computes exactly what the scalar code would (same operations, same order; no
//! fused multiply-add), so results do not depend on whether the lanes are packed.
//!
//! `F64x4` is how lanes are stored (or `F32x4`, for what a pass only reads, widened to f64
//! exactly as it is loaded), and its own arithmetic is plain code that the compiler
//! packs as it sees fit. The solver's passes are generic over `Lanes`, the arithmetic they
//! compute with: `Portable` (that plain code, on any processor) or, on x86_64 processors
//! with AVX2, `Avx2`, one packed instruction per operation. Left to itself the compiler split
//! much of the pass into two-lane halves, so `Avx2` runs the same steps in fewer
//! instructions (BENCHMARKS.md, "Solver lanes with AVX2").

use std::ops::{Add, AddAssign, Mul, Neg, Sub};

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::{
    __m256d, _mm_loadu_ps, _mm256_add_pd, _mm256_cvtps_pd, _mm256_loadu_pd, _mm256_mul_pd,
    _mm256_permute2f128_pd, _mm256_permute4x64_pd, _mm256_set1_pd, _mm256_setzero_pd,
    _mm256_storeu_pd, _mm256_sub_pd, _mm256_unpackhi_pd, _mm256_unpacklo_pd, _mm256_xor_pd,
};

use glam::DVec3;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(32))]
pub struct F64x4(pub [f64; 4]);

impl F64x4 {
    pub const ZERO: F64x4 = F64x4([0.0; 4]);

    #[inline(always)]
    pub fn splat(value: f64) -> F64x4 {
        F64x4([value; 4])
    }

    /// A vector's components in lanes 0 to 2.
    #[inline(always)]
    pub fn from_vec3(v: DVec3) -> F64x4 {
        F64x4([v.x, v.y, v.z, 0.0])
    }

    /// Lanes 0 to 2 as a vector.
    #[inline(always)]
    pub fn to_vec3(self) -> DVec3 {
        DVec3::new(self.0[0], self.0[1], self.0[2])
    }

    /// Lane k of the result is component c of `vectors[k]`, for the three components c:
    /// three vectors transposed into lanes.
    pub fn transpose([a, b, c]: [DVec3; 3]) -> [F64x4; 3] {
        [
            F64x4([a.x, b.x, c.x, 0.0]),
            F64x4([a.y, b.y, c.y, 0.0]),
            F64x4([a.z, b.z, c.z, 0.0]),
        ]
    }

    #[inline(always)]
    pub fn lane(self, k: usize) -> f64 {
        self.0[k]
    }

    /// The scalar dot product of lanes 0 to 2 with `v`, in glam's order of operations.
    #[inline(always)]
    pub fn dot3(self, v: DVec3) -> f64 {
        v.x * self.0[0] + v.y * self.0[1] + v.z * self.0[2]
    }

    /// The cross product of lanes 0 to 2, as glam computes it (products commute exactly);
    /// lane 3 is w·w' − w'·w, zero for the zero padding.
    ///
    /// Written as two products of permuted lanes rather than component by component: the
    /// compiler then packs each product into one instruction, where it split the
    /// component-wise form into halves, which made a step slightly cheaper (BENCHMARKS.md,
    /// "Lane cross product").
    #[inline(always)]
    pub fn cross(self, other: F64x4) -> F64x4 {
        let ([x, y, z, w], [ox, oy, oz, ow]) = (self.0, other.0);
        F64x4([y, z, x, w]) * F64x4([oz, ox, oy, ow])
            - F64x4([oy, oz, ox, ow]) * F64x4([z, x, y, w])
    }

    #[inline(always)]
    fn zip(self, other: F64x4, f: impl Fn(f64, f64) -> f64) -> F64x4 {
        let (a, b) = (self.0, other.0);
        F64x4([f(a[0], b[0]), f(a[1], b[1]), f(a[2], b[2]), f(a[3], b[3])])
    }
}

impl Add for F64x4 {
    type Output = F64x4;
    #[inline(always)]
    fn add(self, other: F64x4) -> F64x4 {
        self.zip(other, |a, b| a + b)
    }
}

impl AddAssign for F64x4 {
    #[inline(always)]
    fn add_assign(&mut self, other: F64x4) {
        *self = *self + other;
    }
}

impl Sub for F64x4 {
    type Output = F64x4;
    #[inline(always)]
    fn sub(self, other: F64x4) -> F64x4 {
        self.zip(other, |a, b| a - b)
    }
}

impl Mul for F64x4 {
    type Output = F64x4;
    #[inline(always)]
    fn mul(self, other: F64x4) -> F64x4 {
        self.zip(other, |a, b| a * b)
    }
}

impl Mul<f64> for F64x4 {
    type Output = F64x4;
    #[inline(always)]
    fn mul(self, scale: f64) -> F64x4 {
        self * F64x4::splat(scale)
    }
}

impl Neg for F64x4 {
    type Output = F64x4;
    #[inline(always)]
    fn neg(self) -> F64x4 {
        F64x4(self.0.map(|a| -a))
    }
}

/// Four lanes stored as f32, for the contact data a pass only reads (directions, levers,
/// spins): half the memory of `F64x4`, and loading widens them to f64 exactly, so the
/// arithmetic stays in f64. A pass streams every contact point through memory, and the
/// narrower record made the large scenes' passes faster (BENCHMARKS.md, "Narrow contact
/// records").
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(16))]
pub struct F32x4(pub [f32; 4]);

impl F32x4 {
    /// Each lane rounded to the nearest f32.
    #[inline(always)]
    pub fn narrowed(wide: F64x4) -> F32x4 {
        let [a, b, c, d] = wide.0;
        F32x4([a as f32, b as f32, c as f32, d as f32])
    }

    /// Each lane widened to f64 (exact).
    #[inline(always)]
    pub fn widened(self) -> F64x4 {
        let [a, b, c, d] = self.0;
        F64x4([f64::from(a), f64::from(b), f64::from(c), f64::from(d)])
    }

    /// Lanes 0 to 2 as a vector.
    #[inline(always)]
    pub fn to_vec3(self) -> DVec3 {
        self.widened().to_vec3()
    }

    /// Three lanes narrowed, as a contact record stores its triples.
    #[inline(always)]
    pub fn narrowed3([x, y, z]: [F64x4; 3]) -> [F32x4; 3] {
        [Self::narrowed(x), Self::narrowed(y), Self::narrowed(z)]
    }
}

/// `v` with each component rounded to the nearest f32, as an `F32x4` would store it: the
/// value a narrowed lane gives back.
#[inline(always)]
pub fn rounded_to_f32(v: DVec3) -> DVec3 {
    F32x4::narrowed(F64x4::from_vec3(v)).to_vec3()
}

/// Asks the processor to bring `item`'s first cache line into its caches, for a read soon
/// of something a jumbled order would otherwise wait for; only a hint, and nothing where
/// the processor has no such instruction.
#[inline(always)]
pub fn prefetch<T>(item: &T) {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse"))]
    // SAFETY: SSE is enabled for this build (the cfg); a prefetch changes nothing the program
    // can observe, and `item` is a valid reference anyway.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
            (item as *const T).cast::<i8>(),
        )
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse")))]
    let _ = item;
}

/// The arithmetic a solver pass computes its lanes with (see the module comment).
pub trait Lanes: Copy {
    type Vector: LaneVector;
    fn load(self, stored: F64x4) -> Self::Vector;
    /// The f32 lanes widened to f64.
    fn load_narrow(self, stored: F32x4) -> Self::Vector;
    /// Three rows of f32 lanes, widened to f64, as columns: lane c of column k is lane k of
    /// row c (lane 3 zero), e.g. three vectors from their components held in lanes.
    fn load_narrow_columns(self, rows: &[F32x4; 3]) -> [Self::Vector; 3];
}

/// Four lanes in registers, loaded from an `F64x4` and stored back to one.
pub trait LaneVector:
    Copy
    + Add<Output = Self>
    + AddAssign
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Mul<f64, Output = Self>
    + Neg<Output = Self>
{
    fn store(self) -> F64x4;
    /// The cross product of lanes 0 to 2, as `F64x4::cross`.
    fn cross(self, other: Self) -> Self;

    #[inline(always)]
    fn lane(self, k: usize) -> f64 {
        self.store().lane(k)
    }

    #[inline(always)]
    fn dot3(self, v: DVec3) -> f64 {
        self.store().dot3(v)
    }
}

/// `F64x4`'s own arithmetic, on any processor.
#[derive(Clone, Copy, Debug)]
pub struct Portable;

impl Lanes for Portable {
    type Vector = F64x4;
    #[inline(always)]
    fn load(self, stored: F64x4) -> F64x4 {
        stored
    }
    #[inline(always)]
    fn load_narrow(self, stored: F32x4) -> F64x4 {
        stored.widened()
    }
    #[inline(always)]
    fn load_narrow_columns(self, [x, y, z]: &[F32x4; 3]) -> [F64x4; 3] {
        let column = |k: usize| F64x4([x.0[k], y.0[k], z.0[k], 0.0].map(f64::from));
        [column(0), column(1), column(2)]
    }
}

impl LaneVector for F64x4 {
    #[inline(always)]
    fn store(self) -> F64x4 {
        self
    }
    #[inline(always)]
    fn cross(self, other: F64x4) -> F64x4 {
        F64x4::cross(self, other)
    }
}

/// Packed AVX2 arithmetic. Only `Avx2::detect` makes one, on a processor that has AVX2, and
/// only an `Avx2` loads or makes `Avx2Vector`s: a vector's existence proves the instructions
/// it runs are there.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
pub struct Avx2(());

#[cfg(target_arch = "x86_64")]
impl Avx2 {
    pub fn detect() -> Option<Avx2> {
        std::arch::is_x86_feature_detected!("avx2").then_some(Avx2(()))
    }
}

#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
pub struct Avx2Vector(__m256d);

#[cfg(target_arch = "x86_64")]
impl Lanes for Avx2 {
    type Vector = Avx2Vector;
    #[inline(always)]
    fn load(self, stored: F64x4) -> Avx2Vector {
        // SAFETY: `self` proves AVX2 (see `Avx2`); the pointer reads the four lanes.
        Avx2Vector(unsafe { _mm256_loadu_pd(stored.0.as_ptr()) })
    }
    #[inline(always)]
    fn load_narrow(self, stored: F32x4) -> Avx2Vector {
        // SAFETY: `self` proves AVX2 (see `Avx2`); the pointer reads the four lanes.
        Avx2Vector(unsafe { _mm256_cvtps_pd(_mm_loadu_ps(stored.0.as_ptr())) })
    }
    #[inline(always)]
    fn load_narrow_columns(self, [x, y, z]: &[F32x4; 3]) -> [Avx2Vector; 3] {
        let [x, y, z] = [x, y, z].map(|row| self.load_narrow(*row).0);
        // SAFETY: `self` proves AVX2 (see `Avx2`).
        unsafe {
            let zero = _mm256_setzero_pd();
            // (x0, y0, x2, y2), (x1, y1, x3, y3), (z0, 0, z2, 0), (z1, 0, z3, 0).
            let xy_even = _mm256_unpacklo_pd(x, y);
            let xy_odd = _mm256_unpackhi_pd(x, y);
            let z_even = _mm256_unpacklo_pd(z, zero);
            let z_odd = _mm256_unpackhi_pd(z, zero);
            [
                Avx2Vector(_mm256_permute2f128_pd(xy_even, z_even, 0x20)),
                Avx2Vector(_mm256_permute2f128_pd(xy_odd, z_odd, 0x20)),
                Avx2Vector(_mm256_permute2f128_pd(xy_even, z_even, 0x31)),
            ]
        }
    }
}

/// The SAFETY of every intrinsic below: an `Avx2Vector` exists only where AVX2 was detected.
#[cfg(target_arch = "x86_64")]
impl LaneVector for Avx2Vector {
    #[inline(always)]
    fn store(self) -> F64x4 {
        let mut stored = F64x4::ZERO;
        // SAFETY: see the impl; the pointer writes the four lanes.
        unsafe { _mm256_storeu_pd(stored.0.as_mut_ptr(), self.0) };
        stored
    }

    #[inline(always)]
    fn cross(self, other: Avx2Vector) -> Avx2Vector {
        // Lanes (y, z, x, w) and (z, x, y, w), as `F64x4::cross` builds them.
        const YZX: i32 = 0b11_00_10_01;
        const ZXY: i32 = 0b11_01_00_10;
        // SAFETY: see the impl.
        unsafe {
            let yzx = |v: __m256d| _mm256_permute4x64_pd::<YZX>(v);
            let zxy = |v: __m256d| _mm256_permute4x64_pd::<ZXY>(v);
            let left = _mm256_mul_pd(yzx(self.0), zxy(other.0));
            let right = _mm256_mul_pd(yzx(other.0), zxy(self.0));
            Avx2Vector(_mm256_sub_pd(left, right))
        }
    }
}

#[cfg(target_arch = "x86_64")]
impl Add for Avx2Vector {
    type Output = Avx2Vector;
    #[inline(always)]
    fn add(self, other: Avx2Vector) -> Avx2Vector {
        // SAFETY: see `impl LaneVector for Avx2Vector`.
        Avx2Vector(unsafe { _mm256_add_pd(self.0, other.0) })
    }
}

#[cfg(target_arch = "x86_64")]
impl AddAssign for Avx2Vector {
    #[inline(always)]
    fn add_assign(&mut self, other: Avx2Vector) {
        *self = *self + other;
    }
}

#[cfg(target_arch = "x86_64")]
impl Sub for Avx2Vector {
    type Output = Avx2Vector;
    #[inline(always)]
    fn sub(self, other: Avx2Vector) -> Avx2Vector {
        // SAFETY: see `impl LaneVector for Avx2Vector`.
        Avx2Vector(unsafe { _mm256_sub_pd(self.0, other.0) })
    }
}

#[cfg(target_arch = "x86_64")]
impl Mul for Avx2Vector {
    type Output = Avx2Vector;
    #[inline(always)]
    fn mul(self, other: Avx2Vector) -> Avx2Vector {
        // SAFETY: see `impl LaneVector for Avx2Vector`.
        Avx2Vector(unsafe { _mm256_mul_pd(self.0, other.0) })
    }
}

#[cfg(target_arch = "x86_64")]
impl Mul<f64> for Avx2Vector {
    type Output = Avx2Vector;
    #[inline(always)]
    fn mul(self, scale: f64) -> Avx2Vector {
        // SAFETY: see `impl LaneVector for Avx2Vector`.
        Avx2Vector(unsafe { _mm256_mul_pd(self.0, _mm256_set1_pd(scale)) })
    }
}

#[cfg(target_arch = "x86_64")]
impl Neg for Avx2Vector {
    type Output = Avx2Vector;
    #[inline(always)]
    fn neg(self) -> Avx2Vector {
        // Flipping the sign bit is what negation does, zeros and NaNs included.
        // SAFETY: see `impl LaneVector for Avx2Vector`.
        Avx2Vector(unsafe { _mm256_xor_pd(self.0, _mm256_set1_pd(-0.0)) })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_compute_what_glam_computes_to_the_bit() {
        let (a, b) = (DVec3::new(0.1, -2.7, 1e-3), DVec3::new(3.3, 0.7, -1.9));
        let (la, lb) = (F64x4::from_vec3(a), F64x4::from_vec3(b));
        assert_eq!((la + lb).to_vec3(), a + b);
        assert_eq!((la - lb).to_vec3(), a - b);
        assert_eq!((la * 0.3).to_vec3(), a * 0.3);
        assert_eq!((-la).to_vec3(), -a);
        assert_eq!(la.dot3(b), b.dot(a));
        assert_eq!(la.cross(lb).to_vec3(), a.cross(b));
        let t = F64x4::transpose([a, b, a + b]);
        assert_eq!([t[0].lane(1), t[1].lane(1), t[2].lane(1)], [b.x, b.y, b.z]);
    }

    /// Both backends give the same bits, the padding lane and signed zeros included.
    #[test]
    fn packed_lanes_compute_what_portable_lanes_compute() {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = Avx2::detect() {
            let a = F64x4([0.1, -2.7, 1e-3, 0.0]);
            let b = F64x4([3.3, 0.7, -1.9, -0.0]);
            let same = |packed: F64x4, portable: F64x4| {
                assert_eq!(packed.0.map(f64::to_bits), portable.0.map(f64::to_bits))
            };
            let (pa, pb) = (avx.load(a), avx.load(b));
            same((pa + pb).store(), a + b);
            same((pa - pb).store(), a - b);
            same((pa * pb).store(), a * b);
            same((pa * 0.3).store(), a * 0.3);
            same((-pa).store(), -a);
            same((-pb).store(), -b);
            same(pa.cross(pb).store(), a.cross(b));
            let narrow = F32x4([0.1, -2.7e30, 1e-40, -0.0]);
            same(avx.load_narrow(narrow).store(), narrow.widened());
            let rows = [
                narrow,
                F32x4([1.5, -0.25, 3e-8, 7.0]),
                F32x4([-9.0, 0.0, 2.5e10, -1.0]),
            ];
            let (packed, portable) = (
                avx.load_narrow_columns(&rows),
                Portable.load_narrow_columns(&rows),
            );
            for (packed, portable) in packed.iter().zip(portable) {
                same(packed.store(), portable);
            }
            // Column 2 is lane 2 of each row.
            let third = [1e-40f32, 3e-8, 2.5e10, 0.0].map(f64::from);
            assert_eq!(Portable.load_narrow_columns(&rows)[2].0, third);
            assert_eq!(pa.dot3(DVec3::X), a.dot3(DVec3::X));
        }
    }
}
