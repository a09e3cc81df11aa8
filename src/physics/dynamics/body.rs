//! A rigid body in the report's state form: centre of mass, orientation matrix, linear and
//! angular momentum, inverse mass and inverse local inertia. Velocities are derived from the
//! momenta, never stored.

use glam::{DMat3, DQuat, DVec3};
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::physics::geometry::aabb::Aabb;
use crate::physics::geometry::gjk::{PosedShape, SupportMap, shape_margin};
use crate::physics::geometry::mass::MassProperties;
use crate::physics::geometry::nearest_surface::NearestSurface;
use crate::physics::geometry::shape::{Shape, ShapeError};

/// Index of a body in its world.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct BodyId(pub u32);

impl BodyId {
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Surface and bulk properties. Pairs combine them as documented in the contact solvers
/// (restitution: the smaller of the two, as in the report).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Material {
    /// kg/m³
    pub density: f64,
    /// Newton's coefficient of restitution ε, in [0, 1].
    pub restitution: f64,
    /// Coulomb friction coefficient μ, ≥ 0.
    pub friction: f64,
}

impl Default for Material {
    fn default() -> Self {
        Material {
            density: 1000.0,
            restitution: 0.3,
            friction: 0.5,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Motion {
    /// Moves under forces and contacts.
    Dynamic,
    /// Never moves: inverse mass and inverse inertia are zero, as in the report.
    Static,
    /// Taken out of the simulation after its state went non-finite; kept for inspection.
    /// Feels no force, moves no more and touches nothing.
    Isolated,
    /// Removed by the user (`World::remove_body`): like `Isolated`, and not drawn. The slot
    /// stays so that the ids of the other bodies stay valid.
    Removed,
}

impl Motion {
    /// Dynamic or static: a body the simulation still moves or collides with.
    pub fn takes_part(self) -> bool {
        matches!(self, Motion::Dynamic | Motion::Static)
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RigidBody {
    pub name: String,
    pub shape: Shape,
    pub material: Material,
    pub motion: Motion,
    /// Centre of mass in shape coordinates: the shape's origin is at
    /// `position - orientation * local_center`.
    pub local_center: DVec3,

    /// Centre of mass C, world.
    pub position: DVec3,
    /// R: its columns are the body's axes in world coordinates.
    pub orientation: DMat3,
    /// L = m v
    pub linear_momentum: DVec3,
    /// World angular momentum A = I_world ω.
    pub angular_momentum: DVec3,

    pub inv_mass: f64,
    pub inv_inertia_local: DMat3,
    /// R I⁻¹ Rᵀ: auxiliary, refreshed whenever the orientation changes.
    pub inv_inertia_world: DMat3,

    /// Accumulated over one step, cleared after integration.
    pub force: DVec3,
    pub torque: DVec3,

    /// Asleep: neither integrated nor solved until something wakes it (see `islands`).
    pub sleeping: bool,
    /// How long the body has been quiet enough to sleep, s.
    pub quiet_time: f64,
}

/// Everything needed to create a body. The pose places the shape's own frame.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyDesc {
    pub name: String,
    pub shape: Shape,
    pub material: Material,
    pub motion: Motion,
    /// Overrides the mass from density while keeping the shape's mass distribution.
    pub mass: Option<f64>,
    pub position: DVec3,
    pub rotation: DQuat,
    pub velocity: DVec3,
    pub angular_velocity: DVec3,
}

#[derive(Debug, Error, PartialEq)]
pub enum BodyError {
    #[error("body '{body}': shape: {source}")]
    Shape { body: String, source: ShapeError },
    #[error("body '{body}': {field} must be finite")]
    NotFinite { body: String, field: &'static str },
    #[error("body '{body}': {field} must be positive, got {value}")]
    NotPositive {
        body: String,
        field: &'static str,
        value: f64,
    },
    #[error("body '{body}': {field} must lie in [{min}, {max}], got {value}")]
    OutOfRange {
        body: String,
        field: &'static str,
        value: f64,
        min: f64,
        max: f64,
    },
}

impl BodyDesc {
    pub fn dynamic(shape: Shape) -> Self {
        BodyDesc {
            name: String::new(),
            shape,
            material: Material::default(),
            motion: Motion::Dynamic,
            mass: None,
            position: DVec3::ZERO,
            rotation: DQuat::IDENTITY,
            velocity: DVec3::ZERO,
            angular_velocity: DVec3::ZERO,
        }
    }

    pub fn fixed(shape: Shape) -> Self {
        BodyDesc {
            motion: Motion::Static,
            ..BodyDesc::dynamic(shape)
        }
    }

    pub fn named(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    pub fn at(mut self, position: DVec3) -> Self {
        self.position = position;
        self
    }

    pub fn rotated(mut self, rotation: DQuat) -> Self {
        self.rotation = rotation;
        self
    }

    pub fn with_velocity(mut self, velocity: DVec3) -> Self {
        self.velocity = velocity;
        self
    }

    pub fn with_angular_velocity(mut self, angular_velocity: DVec3) -> Self {
        self.angular_velocity = angular_velocity;
        self
    }

    pub fn with_material(mut self, material: Material) -> Self {
        self.material = material;
        self
    }

    pub fn with_mass(mut self, mass: f64) -> Self {
        self.mass = Some(mass);
        self
    }

    /// Checks every number a user can get wrong, naming the body and the field.
    pub fn validate(&self) -> Result<(), BodyError> {
        let body = || self.name.clone();
        self.shape.validate().map_err(|source| BodyError::Shape {
            body: body(),
            source,
        })?;
        let vectors = [
            ("position", self.position),
            ("velocity", self.velocity),
            ("angular_velocity", self.angular_velocity),
        ];
        for (field, value) in vectors {
            if !value.is_finite() {
                return Err(BodyError::NotFinite {
                    body: body(),
                    field,
                });
            }
        }
        if !self.rotation.is_finite() || self.rotation.length_squared() < 1e-12 {
            return Err(BodyError::NotFinite {
                body: body(),
                field: "rotation",
            });
        }
        check_positive(&body, "material.density", self.material.density)?;
        if let Some(mass) = self.mass {
            check_positive(&body, "mass", mass)?;
        }
        check_range(
            &body,
            "material.restitution",
            self.material.restitution,
            0.0,
            1.0,
        )?;
        check_range(
            &body,
            "material.friction",
            self.material.friction,
            0.0,
            10.0,
        )
    }
}

fn check_positive(
    body: &dyn Fn() -> String,
    field: &'static str,
    value: f64,
) -> Result<(), BodyError> {
    if !value.is_finite() {
        return Err(BodyError::NotFinite {
            body: body(),
            field,
        });
    }
    if value <= 0.0 {
        return Err(BodyError::NotPositive {
            body: body(),
            field,
            value,
        });
    }
    Ok(())
}

fn check_range(
    body: &dyn Fn() -> String,
    field: &'static str,
    value: f64,
    min: f64,
    max: f64,
) -> Result<(), BodyError> {
    if !value.is_finite() {
        return Err(BodyError::NotFinite {
            body: body(),
            field,
        });
    }
    if !(min..=max).contains(&value) {
        return Err(BodyError::OutOfRange {
            body: body(),
            field,
            value,
            min,
            max,
        });
    }
    Ok(())
}

/// k·I: the same inertia about every axis.
#[inline(always)]
pub fn is_isotropic(m: DMat3) -> bool {
    let k = m.x_axis.x;
    m == DMat3::from_diagonal(DVec3::splat(k))
}

impl RigidBody {
    /// Builds a body from a validated description.
    pub fn from_desc(desc: &BodyDesc) -> Result<RigidBody, BodyError> {
        desc.validate()?;
        let density_props = MassProperties::of_shape(&desc.shape, desc.material.density);
        let props = match desc.mass {
            Some(mass) => density_props.with_mass(mass),
            None => density_props,
        };
        let orientation = DMat3::from_quat(desc.rotation.normalize());
        let position = desc.position + orientation * props.center;
        let (inv_mass, inv_inertia_local) = match desc.motion {
            Motion::Dynamic => (1.0 / props.mass, props.inertia.inverse()),
            Motion::Static | Motion::Isolated | Motion::Removed => (0.0, DMat3::ZERO),
        };
        let mut body = RigidBody {
            name: desc.name.clone(),
            shape: desc.shape.clone(),
            material: desc.material,
            motion: desc.motion,
            local_center: props.center,
            position,
            orientation,
            linear_momentum: DVec3::ZERO,
            angular_momentum: DVec3::ZERO,
            inv_mass,
            inv_inertia_local,
            inv_inertia_world: DMat3::ZERO,
            force: DVec3::ZERO,
            torque: DVec3::ZERO,
            sleeping: false,
            quiet_time: 0.0,
        };
        body.refresh_world_inertia();
        if body.is_dynamic() {
            body.linear_momentum = desc.velocity * props.mass;
            body.angular_momentum = body.inertia_world() * desc.angular_velocity;
        }
        Ok(body)
    }

    pub fn is_dynamic(&self) -> bool {
        self.motion == Motion::Dynamic
    }

    /// Dynamic and not asleep: the bodies a step moves.
    pub fn is_awake(&self) -> bool {
        self.is_dynamic() && !self.sleeping
    }

    pub fn wake(&mut self) {
        self.sleeping = false;
        self.quiet_time = 0.0;
    }

    /// Puts the body to sleep, at rest.
    pub fn sleep(&mut self) {
        self.sleeping = true;
        self.linear_momentum = DVec3::ZERO;
        self.angular_momentum = DVec3::ZERO;
    }

    pub fn mass(&self) -> f64 {
        if self.inv_mass > 0.0 {
            1.0 / self.inv_mass
        } else {
            f64::INFINITY
        }
    }

    /// I_world = R I Rᵀ (only meaningful for dynamic bodies).
    pub fn inertia_world(&self) -> DMat3 {
        self.orientation * self.inv_inertia_local.inverse() * self.orientation.transpose()
    }

    /// I_world⁻¹ = R I⁻¹ Rᵀ. An isotropic inertia (spheres, cubes) is the same in every
    /// frame, and is kept as it is: exact, where the two matrix products would add round-off
    /// (and cost, at every substep of every turning body).
    #[inline(always)]
    pub fn refresh_world_inertia(&mut self) {
        self.inv_inertia_world = if is_isotropic(self.inv_inertia_local) {
            self.inv_inertia_local
        } else {
            self.orientation * self.inv_inertia_local * self.orientation.transpose()
        };
    }

    /// v = L / m
    pub fn velocity(&self) -> DVec3 {
        self.linear_momentum * self.inv_mass
    }

    /// ω = I_world⁻¹ A
    pub fn angular_velocity(&self) -> DVec3 {
        self.inv_inertia_world * self.angular_momentum
    }

    /// Velocity of the material point currently at world position `point`.
    pub fn point_velocity(&self, point: DVec3) -> DVec3 {
        self.velocity() + self.angular_velocity().cross(point - self.position)
    }

    pub fn set_velocity(&mut self, velocity: DVec3) {
        if self.is_dynamic() {
            self.linear_momentum = velocity * self.mass();
            self.wake();
        }
    }

    pub fn set_angular_velocity(&mut self, angular_velocity: DVec3) {
        if self.is_dynamic() {
            self.angular_momentum = self.inertia_world() * angular_velocity;
            self.wake();
        }
    }

    /// A force through the centre of mass.
    pub fn apply_force(&mut self, force: DVec3) {
        self.force += force;
    }

    /// A force at a world point: τ = (x − C) × F.
    pub fn apply_force_at(&mut self, force: DVec3, point: DVec3) {
        self.force += force;
        self.torque += (point - self.position).cross(force);
    }

    /// An instantaneous change of momentum at a world point (a user's push: it wakes the
    /// body). Static bodies ignore it.
    pub fn apply_impulse_at(&mut self, impulse: DVec3, point: DVec3) {
        if self.is_dynamic() {
            self.linear_momentum += impulse;
            self.angular_momentum += (point - self.position).cross(impulse);
            self.wake();
        }
    }

    /// ½ m v² + ½ ω·A
    pub fn kinetic_energy(&self) -> f64 {
        if !self.is_dynamic() {
            return 0.0;
        }
        0.5 * self.velocity().dot(self.linear_momentum)
            + 0.5 * self.angular_velocity().dot(self.angular_momentum)
    }

    /// Orientation as a quaternion (for renderers and snapshots).
    pub fn rotation(&self) -> DQuat {
        DQuat::from_mat3(&self.orientation).normalize()
    }

    /// Where the shape's own origin is in the world.
    pub fn shape_origin(&self) -> DVec3 {
        self.position - self.orientation * self.local_center
    }

    /// Maps a point from shape coordinates to world coordinates.
    pub fn shape_to_world(&self, point: DVec3) -> DVec3 {
        self.position + self.orientation * (point - self.local_center)
    }

    /// World-space support point of the body's shape along a world direction.
    pub fn world_support(&self, direction: DVec3) -> DVec3 {
        let local = self.shape.support(self.orientation.transpose() * direction);
        self.shape_to_world(local)
    }

    /// True when every state number is finite.
    pub fn is_finite(&self) -> bool {
        self.position.is_finite()
            && self.orientation.is_finite()
            && self.linear_momentum.is_finite()
            && self.angular_momentum.is_finite()
    }

    pub fn clear_accumulators(&mut self) {
        self.force = DVec3::ZERO;
        self.torque = DVec3::ZERO;
    }
}

impl<'a> PosedShape<'a> {
    /// The body's shape where the body is.
    pub fn of_body(body: &'a RigidBody) -> Self {
        PosedShape::new(&body.shape, body.shape_origin(), body.orientation)
    }
}

impl Aabb {
    /// The tight box of a body at its current pose.
    pub fn of_body(body: &RigidBody) -> Self {
        Aabb::of_shape(&body.shape, body.shape_origin(), body.orientation)
    }
}

/// A body is its shape where the body is.
impl SupportMap for RigidBody {
    fn core_support(&self, direction: DVec3) -> DVec3 {
        PosedShape::of_body(self).core_support(direction)
    }

    fn margin(&self) -> f64 {
        shape_margin(&self.shape)
    }

    fn inner_point(&self) -> DVec3 {
        self.position
    }

    fn core_segment(&self) -> Option<[DVec3; 2]> {
        PosedShape::of_body(self).core_segment()
    }

    fn nearest_surface(&self, point: DVec3) -> Option<NearestSurface> {
        PosedShape::of_body(self).nearest_surface(point)
    }
}
