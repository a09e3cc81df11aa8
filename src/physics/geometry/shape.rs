//! Collision shapes, in their own local frame.
//!
//! Every convex shape exposes a support function: the point of the shape farthest along a
//! direction. GJK, EPA, bounding boxes and time of impact only ever talk to shapes through it.
//! Capsules and cylinders are aligned with the local y axis.

use std::sync::Arc;

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::physics::geometry::compound::{Compound, MAX_COMPOUND_PARTS};
use crate::physics::geometry::hull::ConvexHull;

/// Smallest extent (m: a radius, half-extent or half-height) a shape may have. Outside
/// [`MIN_EXTENT`, `MAX_EXTENT`], f64 contact tolerances (1e-9 m) and a single-precision
/// renderer stop being meaningful.
pub const MIN_EXTENT: f64 = 1e-4;
/// Largest extent (m) a shape may have; see `MIN_EXTENT`.
pub const MAX_EXTENT: f64 = 1e4;

/// A collision shape in its own local frame, dimensions in metres. The primitives are
/// centred on the origin; hulls and compounds lie wherever their points and parts put them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Shape {
    /// A ball centred on the origin.
    Sphere {
        /// Radius, m.
        radius: f64,
    },
    /// A box centred on the origin, its faces square to the local axes.
    Cuboid {
        /// Half the edge lengths along local x, y and z, m.
        half_extents: DVec3,
    },
    /// A segment from (0, -half_height, 0) to (0, half_height, 0), swept by a sphere of `radius`.
    Capsule {
        /// Half the length of the core segment, m: the caps reach `radius` beyond it.
        half_height: f64,
        /// Radius of the swept sphere, m.
        radius: f64,
    },
    /// A solid cylinder around the local y axis.
    Cylinder {
        /// Half the height, m: the flat caps lie at y = ±half_height.
        half_height: f64,
        /// Radius of the circular cross-section, m.
        radius: f64,
    },
    /// A convex polyhedron in shape coordinates, shared so that cloning a shape is cheap.
    ConvexHull(Arc<ConvexHull>),
    /// A concave body made of convex parts.
    Compound(Arc<Compound>),
}

/// Why `Shape::validate` rejected a shape.
#[derive(Debug, Error, PartialEq)]
pub enum ShapeError {
    /// A dimension is NaN or infinite.
    #[error("{field} must be finite, got {value}")]
    NotFinite {
        /// The dimension, as named in the shape (`radius`, `half_extents.x`, …).
        field: &'static str,
        /// The value it had.
        value: f64,
    },
    /// A dimension lies outside [`MIN_EXTENT`, `MAX_EXTENT`].
    #[error("{field} must lie in [{MIN_EXTENT}, {MAX_EXTENT}] m, got {value}")]
    OutOfRange {
        /// The dimension, as named in the shape (`radius`, `half_extents.x`, …).
        field: &'static str,
        /// The value it had, m.
        value: f64,
    },
    /// A convex hull could not be built from its points, or a hand-built one is invalid.
    #[error("convex hull: {0}")]
    Hull(#[from] crate::physics::geometry::hull::HullError),
    /// A compound has no parts, or a part that is not convex, not finitely posed or not
    /// valid; the message says which.
    #[error("compound: {0}")]
    Compound(String),
    /// A compound has more than `MAX_COMPOUND_PARTS` parts; holds the count.
    #[error("compound: parts: {0}, more than MAX_COMPOUND_PARTS ({MAX_COMPOUND_PARTS})")]
    TooManyParts(usize),
}

impl Shape {
    /// A sphere of `radius` (m). This and the three constructors below check nothing: see
    /// `validate`.
    pub fn sphere(radius: f64) -> Self {
        Shape::Sphere { radius }
    }

    /// A box reaching `half_extents` (m) either side of the origin along each local axis.
    pub fn cuboid(half_extents: DVec3) -> Self {
        Shape::Cuboid { half_extents }
    }

    /// A capsule along local y: the segment of `half_height` (m) either side of the origin,
    /// swept by a sphere of `radius` (m).
    pub fn capsule(half_height: f64, radius: f64) -> Self {
        Shape::Capsule {
            half_height,
            radius,
        }
    }

    /// A solid cylinder along local y, reaching `half_height` (m) either side of the origin,
    /// of `radius` (m).
    pub fn cylinder(half_height: f64, radius: f64) -> Self {
        Shape::Cylinder {
            half_height,
            radius,
        }
    }

    /// The convex hull of a point cloud (quickhull).
    pub fn hull(points: &[DVec3]) -> Result<Self, ShapeError> {
        Ok(Shape::ConvexHull(Arc::new(ConvexHull::from_points(
            points,
        )?)))
    }

    /// The variant's name for messages: "sphere", "cuboid", "capsule", "cylinder", "hull"
    /// or "compound".
    pub fn kind_name(&self) -> &'static str {
        match self {
            Shape::Sphere { .. } => "sphere",
            Shape::Cuboid { .. } => "cuboid",
            Shape::Capsule { .. } => "capsule",
            Shape::Cylinder { .. } => "cylinder",
            Shape::ConvexHull(_) => "hull",
            Shape::Compound(_) => "compound",
        }
    }

    /// Every shape but a compound is convex.
    pub fn is_convex(&self) -> bool {
        !matches!(self, Shape::Compound(_))
    }

    /// Flat faces only (a box, a hull): its contacts come from separating axes and clipping.
    pub fn is_polyhedral(&self) -> bool {
        matches!(self, Shape::Cuboid { .. } | Shape::ConvexHull(_))
    }

    /// Checks that every dimension is finite and within [MIN_EXTENT, MAX_EXTENT].
    pub fn validate(&self) -> Result<(), ShapeError> {
        match self {
            Shape::Sphere { radius } => check_extent("radius", *radius),
            Shape::Cuboid { half_extents } => {
                check_extent("half_extents.x", half_extents.x)?;
                check_extent("half_extents.y", half_extents.y)?;
                check_extent("half_extents.z", half_extents.z)
            }
            Shape::Capsule {
                half_height,
                radius,
            }
            | Shape::Cylinder {
                half_height,
                radius,
            } => {
                check_extent("half_height", *half_height)?;
                check_extent("radius", *radius)
            }
            Shape::ConvexHull(hull) => hull.validate().map_err(ShapeError::from),
            Shape::Compound(compound) => compound.validate(),
        }
    }

    /// The point of the shape farthest along `direction` (local frame). For a compound this is
    /// the support of the convex hull of its parts.
    pub fn support(&self, direction: DVec3) -> DVec3 {
        match self {
            Shape::Sphere { radius } => direction.normalize_or(DVec3::Y) * *radius,
            Shape::Cuboid { half_extents } => sign_or_positive(direction) * *half_extents,
            Shape::Capsule {
                half_height,
                radius,
            } => {
                let tip = DVec3::new(0.0, half_height.copysign(direction.y), 0.0);
                tip + direction.normalize_or(DVec3::Y) * *radius
            }
            Shape::Cylinder {
                half_height,
                radius,
            } => {
                let radial = DVec3::new(direction.x, 0.0, direction.z).normalize_or_zero();
                radial * *radius + DVec3::new(0.0, half_height.copysign(direction.y), 0.0)
            }
            Shape::ConvexHull(hull) => hull.support(direction),
            Shape::Compound(compound) => compound.support(direction),
        }
    }

    /// Local axis-aligned bounds, (min, max). Closed form for the primitives (every contact
    /// query asks for them), the supports along the axes for hulls and compounds.
    pub fn local_bounds(&self) -> (DVec3, DVec3) {
        let half = match *self {
            Shape::Sphere { radius } => DVec3::splat(radius),
            Shape::Cuboid { half_extents } => half_extents,
            Shape::Capsule {
                half_height,
                radius,
            } => DVec3::new(radius, half_height + radius, radius),
            Shape::Cylinder {
                half_height,
                radius,
            } => DVec3::new(radius, half_height, radius),
            Shape::ConvexHull(ref hull) => return hull.bounds(),
            Shape::Compound(_) => return self.bounds_from_supports(),
        };
        (-half, half)
    }

    fn bounds_from_supports(&self) -> (DVec3, DVec3) {
        let max = DVec3::new(
            self.support(DVec3::X).x,
            self.support(DVec3::Y).y,
            self.support(DVec3::Z).z,
        );
        let min = DVec3::new(
            self.support(-DVec3::X).x,
            self.support(-DVec3::Y).y,
            self.support(-DVec3::Z).z,
        );
        (min, max)
    }

    /// For a point on a rounded part of the surface (a sphere, a capsule's sides and ends),
    /// the centre of that rounding in shape coordinates: the core point the surface point
    /// lies a radius away from. None for shapes with flat faces, edges or rims. A round
    /// contact is where the core is nearest the other surface, whichever way the body has
    /// turned: a rolling ball's contact stays under its centre, while the material point
    /// under it rolls up and away.
    pub fn round_core(&self, point: DVec3) -> Option<DVec3> {
        match *self {
            Shape::Sphere { .. } => Some(DVec3::ZERO),
            Shape::Capsule { half_height, .. } => {
                Some(DVec3::Y * point.y.clamp(-half_height, half_height))
            }
            _ => None,
        }
    }

    /// Radius of an origin-centred sphere that holds the shape: the smallest for the
    /// primitives and hulls, the one through the farthest corner of the local bounds for
    /// compounds (at most √3 times the smallest).
    pub fn bounding_radius(&self) -> f64 {
        match *self {
            Shape::Sphere { radius } => radius,
            Shape::Cuboid { half_extents } => half_extents.length(),
            Shape::Capsule {
                half_height,
                radius,
            } => half_height + radius,
            Shape::Cylinder {
                half_height,
                radius,
            } => half_height.hypot(radius),
            Shape::ConvexHull(ref hull) => hull.radius(),
            Shape::Compound(_) => {
                let (min, max) = self.local_bounds();
                min.abs().max(max.abs()).length()
            }
        }
    }
}

/// A rigid transform: rotation then translation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Applied after the rotation: where the posed frame's origin lands (m).
    pub translation: DVec3,
    /// Applied first, about the posed frame's origin; a unit quaternion.
    pub rotation: DQuat,
}

impl Pose {
    /// The pose that leaves every point where it is.
    pub const IDENTITY: Pose = Pose {
        translation: DVec3::ZERO,
        rotation: DQuat::IDENTITY,
    };

    /// The pose that rotates by `rotation`, then translates by `translation` (m).
    pub fn new(translation: DVec3, rotation: DQuat) -> Self {
        Pose {
            translation,
            rotation,
        }
    }

    /// `p` in the posed frame, expressed in the outer frame: rotated, then translated.
    pub fn transform_point(&self, p: DVec3) -> DVec3 {
        self.rotation * p + self.translation
    }
}

fn check_extent(field: &'static str, value: f64) -> Result<(), ShapeError> {
    if !value.is_finite() {
        return Err(ShapeError::NotFinite { field, value });
    }
    if !(MIN_EXTENT..=MAX_EXTENT).contains(&value) {
        return Err(ShapeError::OutOfRange { field, value });
    }
    Ok(())
}

/// Component-wise sign with zero mapped to +1, so a support point is always a vertex.
fn sign_or_positive(v: DVec3) -> DVec3 {
    DVec3::new(1f64.copysign(v.x), 1f64.copysign(v.y), 1f64.copysign(v.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn primitives() -> [Shape; 4] {
        [
            Shape::sphere(0.3),
            Shape::cuboid(DVec3::new(0.1, 0.25, 0.7)),
            Shape::capsule(0.4, 0.15),
            Shape::cylinder(0.2, 0.35),
        ]
    }

    /// The closed-form bounds of the primitives, and the kept bounds of a hull, are what
    /// their support functions give.
    #[test]
    fn closed_form_bounds_match_the_supports() {
        let corners = [0.3, -0.2, 0.5, 0.1, -0.4, 0.25, 0.35, -0.15];
        let points: Vec<DVec3> = (0..8)
            .map(|i| DVec3::new(corners[i], corners[(i + 3) % 8], corners[(i + 5) % 8]))
            .collect();
        let hull = Shape::hull(&points).expect("a hull");
        for shape in primitives().into_iter().chain([hull]) {
            assert_eq!(
                shape.local_bounds(),
                shape.bounds_from_supports(),
                "{}",
                shape.kind_name()
            );
        }
    }

    /// A primitive's bounding radius is the farthest any of its supports reaches: over many
    /// directions none goes beyond it, and the farthest comes within 0.1 % of it.
    #[test]
    fn a_primitive_bounding_radius_is_its_farthest_support() {
        for shape in primitives() {
            let radius = shape.bounding_radius();
            let mut farthest: f64 = 0.0;
            for i in 0..4000 {
                // A spiral over the sphere of directions.
                let z = 1.0 - (i as f64 + 0.5) / 2000.0;
                let angle = i as f64 * 2.399_963;
                let r = (1.0 - z * z).sqrt();
                let direction = DVec3::new(r * angle.cos(), z, r * angle.sin());
                farthest = farthest.max(shape.support(direction).length());
            }
            let name = shape.kind_name();
            assert!(
                farthest <= radius * (1.0 + 1e-12),
                "{name}: {farthest} > {radius}"
            );
            assert!(farthest > radius * 0.999, "{name}: {farthest} < {radius}");
        }
    }

    /// A round shape's surface point farthest along d lies a radius along d from the core
    /// point that `round_core` finds for it; shapes with flat parts have no core.
    #[test]
    fn a_round_surface_point_is_a_radius_out_from_its_core() {
        let round = [(Shape::sphere(0.3), 0.3), (Shape::capsule(0.4, 0.15), 0.15)];
        for (shape, radius) in round {
            for i in 0..200 {
                let z = 1.0 - (i as f64 + 0.5) / 100.0;
                let angle = i as f64 * 2.399_963;
                let r = (1.0 - z * z).sqrt();
                let direction = DVec3::new(r * angle.cos(), z, r * angle.sin());
                let surface = shape.support(direction);
                let core = shape.round_core(surface).expect("round");
                let name = shape.kind_name();
                assert!(
                    (core + direction * radius).distance(surface) < 1e-12,
                    "{name}: {direction}"
                );
            }
        }
        let flat = [Shape::cuboid(DVec3::splat(0.2)), Shape::cylinder(0.3, 0.2)];
        for shape in flat {
            assert_eq!(shape.round_core(shape.support(DVec3::Y)), None);
        }
    }
}
