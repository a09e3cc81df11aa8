//! Closed-form nearest surface point of a box or a cylinder to a point, inside or out.
//!
//! A sphere's core is its centre and the extra points of lying capsules and cylinders are
//! points too (`manifold`), so most contact queries in a mixed pile measure a point against
//! a shape. Against a box or a cylinder that is a clamp in the shape's frame: exact, where
//! GJK needs several iterations (and EPA many more when the point is inside).

use glam::DVec3;

use crate::physics::geometry::shape::Shape;

/// The point of a shape's surface nearest to a query point, in the shape's local frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NearestSurface {
    pub point: DVec3,
    /// Unit, out of the shape, at `point`.
    pub outward_normal: DVec3,
    /// The query point is inside the shape (or on its surface): `point` is then the nearest
    /// way out.
    pub inside: bool,
}

/// The surface point nearest to `p` (local coordinates) for boxes and cylinders; None for
/// other shapes.
pub fn nearest_surface(shape: &Shape, p: DVec3) -> Option<NearestSurface> {
    match *shape {
        Shape::Cuboid { half_extents } => Some(nearest_on_box(half_extents, p)),
        Shape::Cylinder {
            half_height,
            radius,
        } => Some(nearest_on_cylinder(half_height, radius, p)),
        _ => None,
    }
}

fn nearest_on_box(half: DVec3, p: DVec3) -> NearestSurface {
    let clamped = p.clamp(-half, half);
    let offset = p - clamped;
    if offset.length_squared() > f64::MIN_POSITIVE {
        return NearestSurface {
            point: clamped,
            outward_normal: offset.normalize(),
            inside: false,
        };
    }
    let p = clamped;
    // Inside: out through the nearest face (the first of equally near ones).
    let depths = half - p.abs();
    let axis = if depths.x <= depths.y && depths.x <= depths.z {
        0
    } else if depths.y <= depths.z {
        1
    } else {
        2
    };
    let side = 1f64.copysign(p[axis]);
    let mut point = p;
    point[axis] = side * half[axis];
    let mut outward_normal = DVec3::ZERO;
    outward_normal[axis] = side;
    NearestSurface {
        point,
        outward_normal,
        inside: true,
    }
}

fn nearest_on_cylinder(half_height: f64, radius: f64, p: DVec3) -> NearestSurface {
    let radial = DVec3::new(p.x, 0.0, p.z);
    let distance = radial.length();
    // Round the axis, any direction is as near: +x, as the support function picks.
    let out = if distance > 0.0 {
        radial / distance
    } else {
        DVec3::X
    };
    let y = p.y.clamp(-half_height, half_height);
    let rim = if distance > radius {
        out * radius
    } else {
        radial
    };
    let point = DVec3::new(rim.x, y, rim.z);
    let offset = p - point;
    if offset.length_squared() > f64::MIN_POSITIVE {
        return NearestSurface {
            point,
            outward_normal: offset.normalize(),
            inside: false,
        };
    }
    let (p, distance) = (point, distance.min(radius));
    let side_depth = radius - distance;
    let cap_depth = half_height - p.y.abs();
    if side_depth < cap_depth {
        NearestSurface {
            point: DVec3::new(out.x * radius, p.y, out.z * radius),
            outward_normal: out,
            inside: true,
        }
    } else {
        let side = 1f64.copysign(p.y);
        NearestSurface {
            point: DVec3::new(p.x, side * half_height, p.z),
            outward_normal: DVec3::new(0.0, side, 0.0),
            inside: true,
        }
    }
}
