//! Four f64 lanes, for the contact solver's inner loop.
//!
//! glam's f64 vectors compute one component at a time. A contact point's work comes in
//! threes instead: the speeds along its normal and two tangents, and the three components of
//! an impulse. `F64x4` holds such a triple (the fourth lane is padding) and does each
//! operation on all lanes at once; the compiler turns that into packed instructions.
//!
//! Every lane computes exactly what the scalar code would (same operations, same order; no
//! fused multiply-add), so results do not depend on whether the lanes are packed.

use std::ops::{Add, AddAssign, Mul, Neg, Sub};

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

    /// Each vector's components in lanes 0 to 2.
    pub fn from_vec3s([a, b, c]: [DVec3; 3]) -> [F64x4; 3] {
        [Self::from_vec3(a), Self::from_vec3(b), Self::from_vec3(c)]
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
    /// component-wise form into halves, and a pyramid step ran 2 % fewer instructions.
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
}
