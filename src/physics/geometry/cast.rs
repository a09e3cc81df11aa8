//! Casts against one placed shape: a ray, or another convex shape moving along a line.
//!
//! Spheres, cuboids and hulls are hit by a ray analytically (quadratic, slabs, clipping
//! against the face planes); capsules and cylinders, and every shape cast, use conservative
//! advancement along the cast direction on GJK distances. Compounds are cast against part
//! by part. A ray that starts inside a shape hits it at distance 0 with the normal opposite
//! to the ray.

use glam::DVec3;

use crate::physics::geometry::gjk::{PosedShape, SupportMap, gjk_distance};
use crate::physics::geometry::shape::Shape;

/// A surface hit on one shape, before it is attached to a body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeHit {
    /// How far along the ray or cast direction the hit lies (m); 0 when the ray starts
    /// inside the shape or the cast shapes already touch.
    pub distance: f64,
    /// The hit point, world coordinates: on the target's surface, or within the overlap
    /// when the ray or cast starts inside.
    pub point: DVec3,
    /// Unit world normal of the target's surface at `point`, facing the ray or the moving
    /// shape; the opposite of the direction when it starts inside.
    pub normal: DVec3,
}

/// Conservative advancement stops this close to the surface (m, grown with the start gap).
const CAST_TOLERANCE: f64 = 1e-9;
const CAST_MAX_ITERATIONS: u32 = 100;

/// The nearest hit of the ray `origin + t * direction`, t in [0, max_distance], on one
/// placed shape. `direction` must be unit length.
pub fn ray_cast_shape(
    shape: &PosedShape,
    origin: DVec3,
    direction: DVec3,
    max_distance: f64,
) -> Option<ShapeHit> {
    if let Some(parts) = shape.compound_parts() {
        return parts
            .iter()
            .filter_map(|part| ray_cast_shape(part, origin, direction, max_distance))
            .min_by(|x, y| x.distance.total_cmp(&y.distance));
    }
    let local_origin = shape.rotation.transpose() * (origin - shape.origin);
    let local_direction = shape.to_local_direction(direction);
    let local = match shape.shape {
        Shape::Sphere { radius } => ray_sphere(local_origin, local_direction, *radius),
        Shape::Cuboid { half_extents } => ray_box(local_origin, local_direction, *half_extents),
        Shape::ConvexHull(hull) => ray_planes(
            local_origin,
            local_direction,
            hull.faces.iter().map(|f| (f.normal, f.offset)),
        ),
        _ => return cast_support_map(&origin, shape, direction, max_distance),
    };
    let (distance, local_normal) = local.filter(|(t, _)| *t <= max_distance)?;
    let normal = if distance == 0.0 {
        -direction
    } else {
        shape.rotation * local_normal
    };
    Some(ShapeHit {
        distance,
        point: origin + direction * distance,
        normal,
    })
}

/// Ray against a sphere at the origin: the smaller root of |o + t d|² = r².
fn ray_sphere(origin: DVec3, direction: DVec3, radius: f64) -> Option<(f64, DVec3)> {
    let b = origin.dot(direction);
    let c = origin.length_squared() - radius * radius;
    if c <= 0.0 {
        return Some((0.0, DVec3::ZERO));
    }
    let discriminant = b * b - c;
    if b > 0.0 || discriminant < 0.0 {
        return None;
    }
    let t = -b - discriminant.sqrt();
    Some((t, (origin + direction * t) / radius))
}

/// Ray against an origin-centred box: the latest entry over the three slabs.
fn ray_box(origin: DVec3, direction: DVec3, half: DVec3) -> Option<(f64, DVec3)> {
    let planes = (0..3).flat_map(|axis| {
        let n = DVec3::AXES[axis];
        [(n, half[axis]), (-n, half[axis])]
    });
    ray_planes(origin, direction, planes)
}

/// Ray against the intersection of half-spaces n·x ≤ offset: enters at the latest entering
/// plane, leaves at the earliest exiting one.
fn ray_planes(
    origin: DVec3,
    direction: DVec3,
    planes: impl Iterator<Item = (DVec3, f64)>,
) -> Option<(f64, DVec3)> {
    let (mut enter, mut exit) = (0.0_f64, f64::INFINITY);
    let mut normal = DVec3::ZERO;
    for (n, offset) in planes {
        let height = n.dot(origin) - offset;
        let rate = n.dot(direction);
        if rate.abs() < f64::MIN_POSITIVE {
            if height > 0.0 {
                return None;
            }
            continue;
        }
        let t = -height / rate;
        if rate < 0.0 {
            if t > enter {
                enter = t;
                normal = n;
            }
        } else {
            exit = exit.min(t);
        }
        if enter > exit {
            return None;
        }
    }
    Some((enter, normal))
}

/// Moves `moving` along `direction` (unit) until it touches `target`: each advance is the
/// current distance divided by the approach speed along the closest-point normal, which
/// can never overshoot. Returns the point and normal on the target.
pub fn cast_support_map(
    moving: &impl SupportMap,
    target: &impl SupportMap,
    direction: DVec3,
    max_distance: f64,
) -> Option<ShapeHit> {
    let moved = |t: f64| Translated {
        inner: moving,
        offset: direction * t,
    };
    let start = gjk_distance(moving, target);
    if start.intersecting {
        return Some(ShapeHit {
            distance: 0.0,
            point: start.point_b,
            normal: -direction,
        });
    }
    let tolerance = CAST_TOLERANCE * (1.0 + start.distance);
    let mut t = 0.0;
    let mut gjk = start;
    // Where the target was last seen from outside: an advance that lands exactly on the
    // surface reports touching without a normal.
    let (mut point, mut normal) = (start.point_b, -start.normal);
    for _ in 0..CAST_MAX_ITERATIONS {
        if gjk.normal != DVec3::ZERO {
            (point, normal) = (gjk.point_b, -gjk.normal);
        }
        if gjk.distance <= tolerance {
            return Some(ShapeHit {
                distance: t,
                point,
                normal,
            });
        }
        let approach = -direction.dot(normal);
        if approach <= 0.0 {
            return None;
        }
        t += gjk.distance / approach;
        if t > max_distance {
            return None;
        }
        gjk = gjk_distance(&moved(t), target);
    }
    None
}

/// A support map shifted by a fixed offset.
struct Translated<'a, S> {
    inner: &'a S,
    offset: DVec3,
}

impl<S: SupportMap> SupportMap for Translated<'_, S> {
    fn core_support(&self, direction: DVec3) -> DVec3 {
        self.inner.core_support(direction) + self.offset
    }
    fn margin(&self) -> f64 {
        self.inner.margin()
    }
    fn inner_point(&self) -> DVec3 {
        self.inner.inner_point() + self.offset
    }
    fn core_segment(&self) -> Option<[DVec3; 2]> {
        self.inner
            .core_segment()
            .map(|ends| ends.map(|p| p + self.offset))
    }
}
