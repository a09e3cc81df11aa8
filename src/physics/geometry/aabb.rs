//! Axis-aligned bounding boxes (the report's Algorithms 1 and 2), tight at any orientation.
//!
//! A box is tight when each of its six faces touches the shape. For any convex shape the
//! extent along a world axis is the support along that axis, so hulls and compounds use
//! their support function; the primitives use closed forms that give the same numbers faster.

use glam::{DMat3, DVec3};
use serde::{Deserialize, Serialize};

use crate::physics::geometry::shape::Shape;

/// An axis-aligned box from `min` to `max`, in the frame of the points it bounds (world for
/// bodies and broad-phase proxies). It is empty when `min` exceeds `max` on any axis.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Aabb {
    /// The lowest corner: the smallest x, y and z of the box (m).
    pub min: DVec3,
    /// The highest corner: the largest x, y and z of the box (m).
    pub max: DVec3,
}

impl Aabb {
    /// The empty box: the identity of `union`.
    pub const EMPTY: Aabb = Aabb {
        min: DVec3::splat(f64::INFINITY),
        max: DVec3::splat(f64::NEG_INFINITY),
    };

    /// The box from `min` to `max`, as given: nothing checks that `min` ≤ `max`.
    pub fn new(min: DVec3, max: DVec3) -> Self {
        Aabb { min, max }
    }

    /// The box reaching `half_extents` (m) either side of `center` along each axis.
    pub fn from_center_half_extents(center: DVec3, half_extents: DVec3) -> Self {
        Aabb::new(center - half_extents, center + half_extents)
    }

    /// The tight box of `shape` placed with its own origin at `origin` and its axes given by
    /// the columns of `rotation`.
    pub fn of_shape(shape: &Shape, origin: DVec3, rotation: DMat3) -> Self {
        let half = match shape {
            Shape::Sphere { radius } => DVec3::splat(*radius),
            Shape::Cuboid { half_extents } => abs_mat(rotation) * *half_extents,
            Shape::Capsule {
                half_height,
                radius,
            } => rotation.y_axis.abs() * *half_height + DVec3::splat(*radius),
            Shape::Cylinder {
                half_height,
                radius,
            } => cylinder_half_extents(rotation.y_axis, *half_height, *radius),
            Shape::ConvexHull(hull) => return vertex_box(&hull.vertices, origin, rotation),
            Shape::Compound(_) => return support_box(shape, origin, rotation),
        };
        Aabb::from_center_half_extents(origin, half)
    }

    /// Grown by `margin` on every side (fat boxes let a broad phase skip updates while a body
    /// moves less than the margin).
    pub fn fattened(&self, margin: f64) -> Self {
        Aabb::new(
            self.min - DVec3::splat(margin),
            self.max + DVec3::splat(margin),
        )
    }

    /// The union of this box and the same box moved by `displacement`: it holds every point
    /// the shape sweeps while translating.
    pub fn swept(&self, displacement: DVec3) -> Self {
        self.union(&Aabb::new(self.min + displacement, self.max + displacement))
    }

    /// The smallest box that holds both (`EMPTY` holds nothing, so it changes nothing).
    pub fn union(&self, other: &Aabb) -> Self {
        Aabb::new(self.min.min(other.min), self.max.max(other.max))
    }

    /// The report's Algorithm 2: boxes overlap unless one axis separates them. Touching
    /// boxes overlap.
    pub fn overlaps(&self, other: &Aabb) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }

    /// Whether `point` lies in the box; its boundary counts as inside.
    pub fn contains_point(&self, point: DVec3) -> bool {
        self.min.cmple(point).all() && point.cmple(self.max).all()
    }

    /// Whether `other` lies entirely within this box; shared faces count as inside.
    pub fn contains(&self, other: &Aabb) -> bool {
        self.min.cmple(other.min).all() && other.max.cmple(self.max).all()
    }

    /// The midpoint of `min` and `max`.
    pub fn center(&self) -> DVec3 {
        0.5 * (self.min + self.max)
    }

    /// Half the box's size along each axis (m); negative on an axis where it is empty.
    pub fn half_extents(&self) -> DVec3 {
        0.5 * (self.max - self.min)
    }

    /// Sum of the face areas; the usual cost measure of bounding volume trees.
    pub fn surface_area(&self) -> f64 {
        let d = (self.max - self.min).max(DVec3::ZERO);
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }

    /// Slab test: the entry parameter t in [0, max_t] of the ray `origin + t * direction`,
    /// or None if it misses. A ray starting inside enters at t = 0.
    pub fn ray_entry(&self, origin: DVec3, direction: DVec3, max_t: f64) -> Option<f64> {
        let mut t_enter = 0.0_f64;
        let mut t_exit = max_t;
        for axis in 0..3 {
            let (o, d) = (origin[axis], direction[axis]);
            let (lo, hi) = (self.min[axis], self.max[axis]);
            if d.abs() < f64::MIN_POSITIVE {
                if o < lo || o > hi {
                    return None;
                }
                continue;
            }
            let (t0, t1) = ((lo - o) / d, (hi - o) / d);
            t_enter = t_enter.max(t0.min(t1));
            t_exit = t_exit.min(t0.max(t1));
            if t_enter > t_exit {
                return None;
            }
        }
        Some(t_enter)
    }
}

/// Component-wise absolute value of a matrix: |R| h bounds a rotated box exactly.
fn abs_mat(m: DMat3) -> DMat3 {
    DMat3::from_cols(m.x_axis.abs(), m.y_axis.abs(), m.z_axis.abs())
}

/// A cylinder with unit axis `axis`: along world axis i the caps reach h |aᵢ| and the rim
/// disc reaches r √(1 − aᵢ²).
fn cylinder_half_extents(axis: DVec3, half_height: f64, radius: f64) -> DVec3 {
    let rim = (DVec3::ONE - axis * axis).max(DVec3::ZERO);
    axis.abs() * half_height + DVec3::new(rim.x.sqrt(), rim.y.sqrt(), rim.z.sqrt()) * radius
}

/// The box of the vertices turned by `rotation` and moved to `origin`: one pass over the
/// vertices, where the six supports along ±x, ±y, ±z take six.
fn vertex_box(vertices: &[DVec3], origin: DVec3, rotation: DMat3) -> Aabb {
    let (min, max) =
        vertices
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(min, max), &v| {
                let turned = rotation * v;
                (min.min(turned), max.max(turned))
            });
    Aabb::new(origin + min, origin + max)
}

/// Extents from the support function along ±x, ±y, ±z (exact for any convex shape).
fn support_box(shape: &Shape, origin: DVec3, rotation: DMat3) -> Aabb {
    let local_axes = rotation.transpose();
    let reach = |world_dir: DVec3| world_dir.dot(rotation * shape.support(local_axes * world_dir));
    let max = DVec3::new(reach(DVec3::X), reach(DVec3::Y), reach(DVec3::Z));
    let min = -DVec3::new(reach(-DVec3::X), reach(-DVec3::Y), reach(-DVec3::Z));
    Aabb::new(origin + min, origin + max)
}

#[cfg(test)]
mod tests {
    use glam::DQuat;

    use super::*;

    /// A hull's box from its turned vertices is the one its supports along the axes give,
    /// to round-off, at turns all over the sphere.
    #[test]
    fn a_hull_box_is_the_box_of_its_supports() {
        let points: Vec<DVec3> = (0..40)
            .map(|i| {
                let t = i as f64;
                DVec3::new(
                    (1.3 * t).sin(),
                    (0.7 * t).cos() * 0.6,
                    (2.1 * t).sin() * 0.3,
                )
            })
            .collect();
        let hull = Shape::hull(&points).expect("a hull");
        for k in 0..100 {
            let t = k as f64 * 0.37;
            let rotation =
                DMat3::from_quat(DQuat::from_euler(glam::EulerRot::XYZ, t, 2.0 * t, 0.5));
            let origin = DVec3::new(3.0, -1.0, 0.5) * t;
            let by_vertices = Aabb::of_shape(&hull, origin, rotation);
            let by_supports = support_box(&hull, origin, rotation);
            let error = (by_vertices.min - by_supports.min)
                .abs()
                .max((by_vertices.max - by_supports.max).abs())
                .max_element();
            assert!(
                error <= 1e-12 * (1.0 + origin.length()),
                "turn {k}: off by {error:e}"
            );
        }
    }
}
