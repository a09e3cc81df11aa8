//! A small xorshift generator, for reproducible random points without dependencies.

use glam::DVec3;

pub struct XorShift(pub u64);

impl XorShift {
    /// Uniform in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in the box of half extents `half` about the origin.
    pub fn in_box(&mut self, half: DVec3) -> DVec3 {
        DVec3::new(self.next(), self.next(), self.next()) * 2.0 * half - half
    }

    /// Uniform in [-1, 1)³.
    pub fn in_unit_cube(&mut self) -> DVec3 {
        self.in_box(DVec3::ONE)
    }
}
