//! Ray casts and shape casts against the world's bodies (picking, pushing, line of sight,
//! sweeps); each body's shape is hit as `geometry::cast` does. Boxes are tested first, so a
//! far body costs one slab test.

use glam::DVec3;

use crate::physics::dynamics::body::{BodyId, RigidBody};
use crate::physics::geometry::aabb::Aabb;
use crate::physics::geometry::cast::{ShapeHit, cast_support_map, ray_cast_shape};
use crate::physics::geometry::gjk::PosedShape;
use crate::physics::geometry::shape::{Shape, ShapeError};
use crate::physics::world::World;

/// The first body a ray or a cast shape meets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CastHit {
    /// The body hit.
    pub body: BodyId,
    /// Where the surface of the body is hit, world.
    pub point: DVec3,
    /// The body's outward surface normal there (unit).
    pub normal: DVec3,
    /// Distance travelled along the (normalised) direction, m.
    pub distance: f64,
    /// `distance / max_distance`, in [0, 1].
    pub fraction: f64,
}

/// A query given values it cannot answer for.
#[derive(Debug, PartialEq, thiserror::Error)]
pub enum QueryError {
    /// An argument is NaN or infinite.
    #[error("{argument} must be finite")]
    NotFinite {
        /// The argument: `origin`, `direction`, `max_distance` or `rotation`.
        argument: &'static str,
    },
    /// The direction is zero (or too short to normalise), so it points nowhere.
    #[error("direction must not be zero")]
    ZeroDirection,
    /// The rotation quaternion is (nearly) zero.
    #[error("rotation must not be zero")]
    ZeroRotation,
    /// The distance is negative.
    #[error("max_distance must not be negative, got {0}")]
    NegativeDistance(f64),
    /// The cast shape is not valid (a negative radius, say).
    #[error("shape: {0}")]
    Shape(#[from] ShapeError),
}

/// The unit direction, once `origin`, `direction` and `max_distance` are checked.
fn checked_ray(origin: DVec3, direction: DVec3, max_distance: f64) -> Result<DVec3, QueryError> {
    let finite = |argument, ok: bool| ok.then_some(()).ok_or(QueryError::NotFinite { argument });
    finite("origin", origin.is_finite())?;
    finite("direction", direction.is_finite())?;
    finite("max_distance", max_distance.is_finite())?;
    if max_distance < 0.0 {
        return Err(QueryError::NegativeDistance(max_distance));
    }
    direction.try_normalize().ok_or(QueryError::ZeroDirection)
}

/// The nearest body hit by a ray; `direction` need not be unit. Boxes are tested first so
/// that far bodies cost one slab test. Non-finite or negative arguments and a zero
/// direction are errors.
pub fn ray_cast(
    bodies: &[RigidBody],
    origin: DVec3,
    direction: DVec3,
    max_distance: f64,
) -> Result<Option<CastHit>, QueryError> {
    let direction = checked_ray(origin, direction, max_distance)?;
    Ok(nearest_hit(bodies, max_distance, |body, limit| {
        Aabb::of_body(body).ray_entry(origin, direction, limit)?;
        ray_cast_shape(&PosedShape::of_body(body), origin, direction, limit)
    }))
}

/// The first body met by the posed shape `cast` moving along `direction` (need not be unit)
/// up to `max_distance`. The point is on the body, the normal the body's. An invalid shape,
/// a non-finite pose or argument, a negative distance and a zero direction are errors.
pub fn shape_cast(
    bodies: &[RigidBody],
    cast: &PosedShape,
    direction: DVec3,
    max_distance: f64,
) -> Result<Option<CastHit>, QueryError> {
    cast.shape.validate()?;
    if !cast.rotation.is_finite() {
        return Err(QueryError::NotFinite {
            argument: "rotation",
        });
    }
    let direction = checked_ray(cast.origin, direction, max_distance)?;
    Ok(checked_shape_cast(bodies, cast, direction, max_distance))
}

/// `shape_cast` with its arguments checked and `direction` of unit length.
fn checked_shape_cast(
    bodies: &[RigidBody],
    cast: &PosedShape,
    direction: DVec3,
    max_distance: f64,
) -> Option<CastHit> {
    if let Some(parts) = cast.compound_parts() {
        return parts
            .iter()
            .filter_map(|part| checked_shape_cast(bodies, part, direction, max_distance))
            .min_by(|x, y| x.distance.total_cmp(&y.distance));
    }
    let sweep = Aabb::of_shape(cast.shape, cast.origin, cast.rotation);
    nearest_hit(bodies, max_distance, |body, limit| {
        let swept = sweep.swept(direction * limit);
        if !swept.overlaps(&Aabb::of_body(body)) {
            return None;
        }
        let target = PosedShape::of_body(body);
        match target.compound_parts() {
            Some(parts) => parts
                .iter()
                .filter_map(|part| cast_support_map(cast, part, direction, limit))
                .min_by(|x, y| x.distance.total_cmp(&y.distance)),
            None => cast_support_map(cast, &target, direction, limit),
        }
    })
}

/// Runs `hit` on every body with the best distance so far as its limit.
fn nearest_hit(
    bodies: &[RigidBody],
    max_distance: f64,
    mut hit: impl FnMut(&RigidBody, f64) -> Option<ShapeHit>,
) -> Option<CastHit> {
    let mut best: Option<CastHit> = None;
    for (index, body) in bodies.iter().enumerate() {
        let limit = best.map_or(max_distance, |b| b.distance);
        if let Some(h) = hit(body, limit).filter(|h| h.distance <= limit) {
            best = Some(CastHit {
                body: BodyId(index as u32),
                point: h.point,
                normal: h.normal,
                distance: h.distance,
                fraction: if max_distance > 0.0 {
                    h.distance / max_distance
                } else {
                    0.0
                },
            });
        }
    }
    best
}

impl World {
    /// The nearest body hit by the ray from `origin` along `direction` within `max_distance`
    /// (see `ray_cast` for the errors).
    pub fn ray_cast(
        &self,
        origin: DVec3,
        direction: DVec3,
        max_distance: f64,
    ) -> Result<Option<CastHit>, QueryError> {
        ray_cast(self.bodies(), origin, direction, max_distance)
    }

    /// The first body met by `shape`, placed at `origin` with `rotation` (need not be unit),
    /// moving along `direction` within `max_distance` (see `shape_cast` for the errors).
    pub fn shape_cast(
        &self,
        shape: &Shape,
        origin: DVec3,
        rotation: glam::DQuat,
        direction: DVec3,
        max_distance: f64,
    ) -> Result<Option<CastHit>, QueryError> {
        // A non-finite rotation stays so through `normalize`, and `shape_cast` refuses it.
        // As a body's rotation: a quaternion this short has no direction to normalise to.
        if rotation.length() < 1e-6 {
            return Err(QueryError::ZeroRotation);
        }
        let rotation = rotation.normalize();
        let cast = PosedShape::new(shape, origin, glam::DMat3::from_quat(rotation));
        shape_cast(self.bodies(), &cast, direction, max_distance)
    }
}
