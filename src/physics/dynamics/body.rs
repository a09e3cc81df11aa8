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
use crate::physics::world::MAX_BODIES;

/// A body's handle, as `World::add_body` hands it out: its slot in `World::bodies` in the
/// low `BodyId::INDEX_BITS` bits, and the slot's generation above them. A removed body's
/// slot is reused under the next generation, so the removed body's id is refused from then
/// on (`World::get_body` answers None) instead of naming the new body. `BodyId(i)` is slot
/// `i` at generation 0, as the world's internal lists (pairs, manifolds) spell their bodies,
/// and as snapshots written before generations stored them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct BodyId(pub u32);

impl BodyId {
    /// Bits of the slot index: 131 072 slots, more than `MAX_BODIES`.
    pub const INDEX_BITS: u32 = 17;
    /// The last generation of a slot; a slot removed at it is never reused, so an id is
    /// never aliased.
    pub const MAX_GENERATION: u32 = (1 << (32 - Self::INDEX_BITS)) - 1;

    /// The id of slot `index` at `generation` (at most `MAX_GENERATION`).
    pub fn new(index: usize, generation: u32) -> Self {
        debug_assert!(index < 1 << Self::INDEX_BITS && generation <= Self::MAX_GENERATION);
        BodyId((generation << Self::INDEX_BITS) | index as u32)
    }

    /// The id as an index into `World::bodies`.
    pub fn index(self) -> usize {
        (self.0 & ((1 << Self::INDEX_BITS) - 1)) as usize
    }

    /// How many times the slot had been freed when this id was handed out.
    pub fn generation(self) -> u32 {
        self.0 >> Self::INDEX_BITS
    }
}

/// Surface and bulk properties. Pairs combine them as documented in the contact solvers
/// (restitution: the smaller of the two, as in the report; friction: the geometric mean
/// √(μa μb)).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Material {
    /// Density, kg/m³, > 0: gives the mass unless `BodyDesc::mass` overrides it.
    pub density: f64,
    /// Newton's coefficient of restitution ε, in [0, 1].
    pub restitution: f64,
    /// Coulomb friction coefficient μ, in [0, 10].
    pub friction: f64,
}

impl Material {
    /// Density positive, restitution in [0, 1], friction in [0, `MAX_FRICTION`]: checked for
    /// a new body (`BodyDesc::validate`) and a restored one (`WorldSnapshot::check`) alike.
    /// `body` names the body in the error.
    pub fn validate(&self, body: &str) -> Result<(), BodyError> {
        let body = || body.to_string();
        check_positive(&body, "material.density", self.density)?;
        check_range(&body, "material.restitution", self.restitution, 0.0, 1.0)?;
        check_range(&body, "material.friction", self.friction, 0.0, MAX_FRICTION)
    }
}

/// The largest friction coefficient a body may have.
pub const MAX_FRICTION: f64 = 10.0;

impl Default for Material {
    fn default() -> Self {
        Material {
            density: 1000.0,
            restitution: 0.3,
            friction: 0.5,
        }
    }
}

/// How a body takes part in the simulation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Motion {
    /// Moves under forces and contacts.
    Dynamic,
    /// Never moves: inverse mass and inverse inertia are zero, as in the report.
    Static,
    /// Moved by its own velocity (`World::set_kinematic_velocity`) or toward a target pose
    /// (`World::set_kinematic_target`), never by forces or contacts: infinite mass (inverse
    /// mass and inertia zero) for everything it touches, which it carries and pushes.
    Kinematic,
    /// Taken out of the simulation after its state went non-finite; kept for inspection.
    /// Feels no force, moves no more and touches nothing.
    Isolated,
    /// Removed by the user (`World::remove_body`): like `Isolated`, and not drawn. The slot
    /// stays so that the ids of the other bodies stay valid.
    Removed,
}

impl Motion {
    /// Dynamic, kinematic or static: a body the simulation still moves or collides with.
    pub fn takes_part(self) -> bool {
        matches!(self, Motion::Dynamic | Motion::Kinematic | Motion::Static)
    }

    /// Dynamic or kinematic: a body that a step may move.
    pub fn moves(self) -> bool {
        matches!(self, Motion::Dynamic | Motion::Kinematic)
    }
}

/// A body of a world, in the report's state form: centre of mass `position`, `orientation`
/// matrix, `linear_momentum` and `angular_momentum` (world frame), with its inverse mass
/// and inverse inertia. Velocities are derived from the momenta and never stored.
///
/// Bodies are made from a [`BodyDesc`] by `World::add_body`, read with `World::body` and
/// changed through `World::body_mut`; the next step looks at a changed body again. Prefer
/// the methods to writing fields: `set_velocity`, `set_angular_velocity` and
/// `apply_impulse_at` convert to momenta and wake the body; `apply_force` and
/// `apply_force_at` act over the next step (and wake a sleeping body then). After writing
/// `orientation` (a rotation matrix), call `refresh_world_inertia`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RigidBody {
    /// The name given in its `BodyDesc` (may be empty), used in errors and `Fault`s.
    pub name: String,
    /// The shape, in shape coordinates (see `local_center`).
    pub shape: Shape,
    /// Density, restitution and friction.
    pub material: Material,
    /// Whether the body moves, stays put, or has been taken out.
    pub motion: Motion,
    /// Centre of mass in shape coordinates: the shape's origin is at
    /// `position - orientation * local_center`.
    pub local_center: DVec3,

    /// Centre of mass C, world, m.
    pub position: DVec3,
    /// R: its columns are the body's axes in world coordinates.
    pub orientation: DMat3,
    /// L = m v, world, kg·m/s.
    pub linear_momentum: DVec3,
    /// Angular momentum about the centre of mass A = I_world ω, world, kg·m²/s.
    pub angular_momentum: DVec3,

    /// 1/m, 1/kg; zero for a body created static.
    pub inv_mass: f64,
    /// I⁻¹ about the centre of mass in body axes, 1/(kg·m²); zero for a body created
    /// static.
    pub inv_inertia_local: DMat3,
    /// R I⁻¹ Rᵀ: auxiliary, refreshed whenever the orientation changes.
    pub inv_inertia_world: DMat3,

    /// Force through the centre of mass, world, N, accumulated for the next step, which
    /// applies it and clears it.
    pub force: DVec3,
    /// Torque about the centre of mass, world, N·m; accumulated and cleared with `force`.
    pub torque: DVec3,

    /// Asleep: neither integrated nor solved until something wakes it (see `islands`).
    pub sleeping: bool,
    /// How long the body has been quiet enough to sleep, s.
    pub quiet_time: f64,
    /// A kinematic body's velocity, world, m/s (its momenta stay zero: infinite mass).
    #[serde(default)]
    pub kinematic_velocity: DVec3,
    /// A kinematic body's angular velocity, world, rad/s.
    #[serde(default)]
    pub kinematic_spin: DVec3,
    /// The pose a kinematic body reaches at the end of the next step (position of its
    /// shape's origin, rotation), set by `World::set_kinematic_target`.
    #[serde(default)]
    pub kinematic_target: Option<(DVec3, DQuat)>,
    /// `BodyDesc::mass`, kept so that a body switched back to dynamic gets the mass it was
    /// made with.
    #[serde(default)]
    pub mass_override: Option<f64>,
}

/// Everything needed to create a body (`World::add_body`), built from `dynamic` or `fixed`
/// and the `with_*` methods. The pose places the shape's own frame.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyDesc {
    /// Names the body in errors and `Fault`s; may be empty.
    pub name: String,
    /// The shape, in its own coordinates.
    pub shape: Shape,
    /// Density, restitution and friction.
    pub material: Material,
    /// `Dynamic`, `Kinematic` or `Static` (the other kinds are states a world puts bodies
    /// in).
    pub motion: Motion,
    /// Overrides the mass from density, kg, while keeping the shape's mass distribution.
    pub mass: Option<f64>,
    /// Where the shape's origin is, world, m (not the centre of mass).
    pub position: DVec3,
    /// Orientation of the shape's frame; normalised on creation, must not be zero.
    pub rotation: DQuat,
    /// Initial velocity of the centre of mass, world, m/s (a kinematic body keeps it);
    /// ignored for static bodies.
    pub velocity: DVec3,
    /// Initial angular velocity, world, rad/s (a kinematic body keeps it); ignored for
    /// static bodies.
    pub angular_velocity: DVec3,
}

/// Why `BodyDesc::validate` refused a description. `body` is the body's name and `field`
/// the offending field as `BodyDesc` spells it (`"material.friction"`).
#[derive(Debug, Error, PartialEq)]
pub enum BodyError {
    /// The shape is not valid.
    #[error("body '{body}': shape: {source}")]
    Shape {
        /// The body's name.
        body: String,
        /// What is wrong with the shape.
        source: ShapeError,
    },
    /// A number is NaN or infinite, or the rotation quaternion is (nearly) zero.
    #[error("body '{body}': {field} must be finite")]
    NotFinite {
        /// The body's name.
        body: String,
        /// The field.
        field: &'static str,
    },
    /// A density or mass is zero or negative.
    #[error("body '{body}': {field} must be positive, got {value}")]
    NotPositive {
        /// The body's name.
        body: String,
        /// The field.
        field: &'static str,
        /// The value given.
        value: f64,
    },
    /// The density or mass gives a mass or inertia whose inverse is not a finite positive
    /// number (a density of 1e-320 kg/m³, say): the body could not be moved by anything.
    #[error(
        "body '{body}': {field} gives a mass of {mass} kg, whose mass or inertia cannot be \
         inverted to a finite number"
    )]
    MassNotInvertible {
        /// The body's name.
        body: String,
        /// The field the mass came from: `mass` or `material.density`.
        field: &'static str,
        /// The mass it gave, kg.
        mass: f64,
    },
    /// The velocity is finite but the momentum or kinetic energy it gives is beyond
    /// `MAX_BODY_ENERGY`: 1e300 m/s on a body of 1e10 kg, or 1e160 m/s on a kilogram.
    #[error(
        "body '{body}': {field} gives a momentum or kinetic energy above {MAX_BODY_ENERGY:e} \
         (the most one body may carry, so that the totals of {MAX_BODIES} bodies stay finite)"
    )]
    EnergyTooLarge {
        /// The body's name.
        body: String,
        /// `velocity` or `angular_velocity`.
        field: &'static str,
    },
    /// A coefficient lies outside its range.
    #[error("body '{body}': {field} must lie in [{min}, {max}], got {value}")]
    OutOfRange {
        /// The body's name.
        body: String,
        /// The field.
        field: &'static str,
        /// The value given.
        value: f64,
        /// Lowest allowed value.
        min: f64,
        /// Highest allowed value.
        max: f64,
    },
}

impl BodyDesc {
    /// A dynamic body of `shape`: unnamed, at the origin, unrotated, at rest, with the
    /// default material and its mass from density.
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

    /// As `dynamic`, but static: the body never moves (floors, walls).
    pub fn fixed(shape: Shape) -> Self {
        BodyDesc {
            motion: Motion::Static,
            ..BodyDesc::dynamic(shape)
        }
    }

    /// As `dynamic`, but kinematic: moved by its velocity (`with_velocity`,
    /// `with_angular_velocity`, `World::set_kinematic_velocity`) or a target pose, never by
    /// forces or contacts.
    pub fn kinematic(shape: Shape) -> Self {
        BodyDesc {
            motion: Motion::Kinematic,
            ..BodyDesc::dynamic(shape)
        }
    }

    /// Sets `name`.
    pub fn named(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    /// Sets `position`: the shape's origin, world, m.
    pub fn at(mut self, position: DVec3) -> Self {
        self.position = position;
        self
    }

    /// Sets `rotation`.
    pub fn rotated(mut self, rotation: DQuat) -> Self {
        self.rotation = rotation;
        self
    }

    /// Sets `velocity`, m/s.
    pub fn with_velocity(mut self, velocity: DVec3) -> Self {
        self.velocity = velocity;
        self
    }

    /// Sets `angular_velocity`, rad/s.
    pub fn with_angular_velocity(mut self, angular_velocity: DVec3) -> Self {
        self.angular_velocity = angular_velocity;
        self
    }

    /// Sets `material`.
    pub fn with_material(mut self, material: Material) -> Self {
        self.material = material;
        self
    }

    /// Sets `mass`, kg, in place of the mass from density.
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
        self.material.validate(&self.name)?;
        if let Some(mass) = self.mass {
            check_positive(&body, "mass", mass)?;
        }
        Ok(())
    }
}

impl BodyError {
    /// The body's name.
    pub fn body(&self) -> &str {
        match self {
            BodyError::Shape { body, .. }
            | BodyError::NotFinite { body, .. }
            | BodyError::EnergyTooLarge { body, .. }
            | BodyError::NotPositive { body, .. }
            | BodyError::MassNotInvertible { body, .. }
            | BodyError::OutOfRange { body, .. } => body,
        }
    }

    /// The offending field, as `BodyDesc` spells it (`shape` for any shape error).
    pub fn field(&self) -> &'static str {
        match self {
            BodyError::Shape { .. } => "shape",
            BodyError::NotFinite { field, .. }
            | BodyError::EnergyTooLarge { field, .. }
            | BodyError::NotPositive { field, .. }
            | BodyError::MassNotInvertible { field, .. }
            | BodyError::OutOfRange { field, .. } => field,
        }
    }

    /// What is wrong with the field, with the value found, for messages that name the body
    /// and field their own way.
    pub fn reason(&self) -> String {
        match self {
            BodyError::Shape { source, .. } => source.to_string(),
            BodyError::NotFinite { .. } => "must be finite".into(),
            BodyError::EnergyTooLarge { .. } => {
                format!("gives a momentum or kinetic energy above {MAX_BODY_ENERGY:e}")
            }
            BodyError::NotPositive { value, .. } => format!("must be positive, got {value}"),
            BodyError::OutOfRange {
                value, min, max, ..
            } => format!("must lie in [{min}, {max}], got {value}"),
            BodyError::MassNotInvertible { mass, .. } => {
                format!("gives a mass of {mass} kg, too small or too large to simulate")
            }
        }
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

/// 1/m and I⁻¹ of a dynamic body, or why they cannot be inverted (`field` is where the
/// mass came from: `mass` when given, else `material.density`).
fn dynamic_inverses(
    props: &MassProperties,
    body: &str,
    mass_given: bool,
) -> Result<(f64, DMat3), BodyError> {
    let (inv_mass, inv_inertia) = (
        1.0 / props.mass,
        with_inertia_floor(props.inertia).inverse(),
    );
    let invertible = inv_mass.is_finite() && inv_inertia.is_finite();
    if !(invertible && props.inertia.is_finite()) {
        return Err(BodyError::MassNotInvertible {
            body: body.to_string(),
            field: if mass_given {
                "mass"
            } else {
                "material.density"
            },
            mass: props.mass,
        });
    }
    Ok((inv_mass, inv_inertia))
}

/// The smallest principal moment of a dynamic body's inertia, as a share of its largest.
/// Below it a rod or needle (a box 1 mm thick and 1 m long has 2e-6) was spun about its
/// own axis by a glancing contact faster than a step can follow, and gained energy without
/// bound. Only rods thinner than about 1/140 of their length are lifted, and only in their
/// spin about their own axis (BENCHMARKS.md, "Inertia floor").
pub const MIN_INERTIA_RATIO: f64 = 1e-4;

/// `inertia` raised by the same amount about every axis, just enough that its smallest
/// principal moment is `MIN_INERTIA_RATIO` of its largest (unchanged when it already is).
/// Adding k·I keeps the principal axes and the larger moments nearly as they were.
fn with_inertia_floor(inertia: DMat3) -> DMat3 {
    let [smallest, largest] = principal_extremes(inertia);
    let lift = (MIN_INERTIA_RATIO * largest - smallest) / (1.0 - MIN_INERTIA_RATIO);
    if lift > 0.0 {
        inertia + DMat3::from_diagonal(DVec3::splat(lift))
    } else {
        inertia
    }
}

/// The smallest and largest eigenvalues of a symmetric 3×3 matrix, in closed form (the
/// trigonometric solution of its characteristic cubic).
fn principal_extremes(m: DMat3) -> [f64; 2] {
    let off = m.y_axis.x.powi(2) + m.z_axis.x.powi(2) + m.z_axis.y.powi(2);
    let diagonal = DVec3::new(m.x_axis.x, m.y_axis.y, m.z_axis.z);
    if off == 0.0 {
        return [diagonal.min_element(), diagonal.max_element()];
    }
    let mean = diagonal.element_sum() / 3.0;
    let spread = (((diagonal - mean).length_squared() + 2.0 * off) / 6.0).sqrt();
    let shifted = (m - DMat3::from_diagonal(DVec3::splat(mean))) * (1.0 / spread);
    let angle = (0.5 * shifted.determinant()).clamp(-1.0, 1.0).acos() / 3.0;
    let largest = mean + 2.0 * spread * angle.cos();
    let smallest = mean + 2.0 * spread * (angle + 2.0 * std::f64::consts::FRAC_PI_3).cos();
    [smallest, largest]
}

/// k·I: the same inertia about every axis.
#[inline(always)]
pub fn is_isotropic(m: DMat3) -> bool {
    let k = m.x_axis.x;
    m == DMat3::from_diagonal(DVec3::splat(k))
}

/// The most kinetic energy (J), and the most linear or angular momentum along any axis
/// (kg·m/s, kg·m²/s), one body may carry: far beyond anything physical, and small enough that the world's
/// kinetic energy and momentum summed over `MAX_BODIES` bodies stay finite.
pub const MAX_BODY_ENERGY: f64 = 1e303;
const _: () = assert!(MAX_BODY_ENERGY * MAX_BODIES as f64 <= f64::MAX);

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
            Motion::Dynamic => dynamic_inverses(&props, &desc.name, desc.mass.is_some())?,
            Motion::Kinematic | Motion::Static | Motion::Isolated | Motion::Removed => {
                (0.0, DMat3::ZERO)
            }
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
            kinematic_velocity: DVec3::ZERO,
            kinematic_spin: DVec3::ZERO,
            kinematic_target: None,
            mass_override: desc.mass,
        };
        body.refresh_world_inertia();
        if body.is_dynamic() {
            body.linear_momentum = desc.velocity * props.mass;
            body.angular_momentum = body.inertia_world() * desc.angular_velocity;
        }
        if body.is_kinematic() {
            body.kinematic_velocity = desc.velocity;
            body.kinematic_spin = desc.angular_velocity;
        }
        if let Some(field) = body.energy_beyond_limit(["velocity", "angular_velocity"]) {
            let body = desc.name.clone();
            return Err(BodyError::EnergyTooLarge { body, field });
        }
        Ok(body)
    }

    /// Which of the linear and the angular motion (named by `fields`) carries a momentum or
    /// a kinetic energy above `MAX_BODY_ENERGY`, if either does. A finite speed times a huge
    /// mass can overflow, and so can ½ m v² when the momentum does not, or the sum of many
    /// bodies' energies when each does not.
    pub fn energy_beyond_limit(&self, fields: [&'static str; 2]) -> Option<&'static str> {
        let motions = [
            (self.linear_momentum, self.velocity()),
            (self.angular_momentum, self.angular_velocity()),
        ];
        let beyond = |(momentum, velocity): (DVec3, DVec3)| {
            let energy = 0.5 * velocity.dot(momentum);
            // By component: a length would square 1e155 into infinity. Written so that NaN
            // counts as beyond.
            let largest = momentum.abs().max_element();
            !(largest <= MAX_BODY_ENERGY && energy <= MAX_BODY_ENERGY)
        };
        (motions.into_iter().zip(fields))
            .find_map(|(motion, field)| beyond(motion).then_some(field))
    }

    /// Moved by forces and contacts (`Motion::Dynamic`), asleep or not.
    pub fn is_dynamic(&self) -> bool {
        self.motion == Motion::Dynamic
    }

    /// Moved by its velocity or a target pose only (`Motion::Kinematic`).
    pub fn is_kinematic(&self) -> bool {
        self.motion == Motion::Kinematic
    }

    /// Dynamic or kinematic and not asleep: the bodies a step moves.
    pub fn is_awake(&self) -> bool {
        self.motion.moves() && !self.sleeping
    }

    /// The mass properties a dynamic body of this shape, material and `mass_override` has.
    pub(crate) fn dynamic_mass_properties(&self) -> Result<(f64, DMat3), BodyError> {
        let density_props = MassProperties::of_shape(&self.shape, self.material.density);
        let props = match self.mass_override {
            Some(mass) => density_props.with_mass(mass),
            None => density_props,
        };
        dynamic_inverses(&props, &self.name, self.mass_override.is_some())
    }

    /// Wakes the body and restarts its quiet time; the momenta are left as they are.
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

    /// m, kg; infinite when the inverse mass is zero (a static body).
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

    /// v = L / m, world, m/s (a kinematic body's own velocity).
    pub fn velocity(&self) -> DVec3 {
        if self.is_kinematic() {
            return self.kinematic_velocity;
        }
        self.linear_momentum * self.inv_mass
    }

    /// ω = I_world⁻¹ A, world, rad/s (a kinematic body's own angular velocity).
    pub fn angular_velocity(&self) -> DVec3 {
        if self.is_kinematic() {
            return self.kinematic_spin;
        }
        self.inv_inertia_world * self.angular_momentum
    }

    /// Velocity of the material point currently at world position `point`, m/s.
    pub fn point_velocity(&self, point: DVec3) -> DVec3 {
        self.velocity() + self.angular_velocity().cross(point - self.position)
    }

    /// Sets the centre of mass's velocity, world, m/s (as L = m v) and wakes the body;
    /// ignored unless the body is dynamic.
    pub fn set_velocity(&mut self, velocity: DVec3) {
        if self.is_dynamic() {
            self.linear_momentum = velocity * self.mass();
            self.wake();
        }
    }

    /// Sets ω, world, rad/s (as A = I_world ω) and wakes the body; ignored unless the body
    /// is dynamic.
    pub fn set_angular_velocity(&mut self, angular_velocity: DVec3) {
        if self.is_dynamic() {
            self.angular_momentum = self.inertia_world() * angular_velocity;
            self.wake();
        }
    }

    /// Adds a force through the centre of mass, world, N, for the next step.
    pub fn apply_force(&mut self, force: DVec3) {
        self.force += force;
    }

    /// Adds a force, N, at a world point for the next step: τ = (x − C) × F.
    pub fn apply_force_at(&mut self, force: DVec3, point: DVec3) {
        self.force += force;
        self.torque += (point - self.position).cross(force);
    }

    /// An instantaneous change of momentum, N·s, at a world point (a user's push: it wakes
    /// the body). Only dynamic bodies take it.
    pub fn apply_impulse_at(&mut self, impulse: DVec3, point: DVec3) {
        if self.is_dynamic() {
            self.linear_momentum += impulse;
            self.angular_momentum += (point - self.position).cross(impulse);
            self.wake();
        }
    }

    /// ½ m v² + ½ ω·A, J; zero unless the body is dynamic.
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

    /// Zeroes the accumulated force and torque.
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

#[cfg(test)]
mod tests {
    use super::*;

    /// R diag(moments) Rᵀ for a rotation that mixes all three axes.
    fn turned(moments: DVec3) -> DMat3 {
        let r = DMat3::from_quat(DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 0.7));
        r * DMat3::from_diagonal(moments) * r.transpose()
    }

    #[test]
    fn principal_extremes_are_the_moments_of_a_turned_tensor() {
        for moments in [
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(5.0, 5.0, 1e-6),
            DVec3::new(2.0, 2.0, 2.0),
        ] {
            let [smallest, largest] = principal_extremes(turned(moments));
            // Round-off of the rotation and the cubic's solution, relative to the largest.
            let tolerance = 1e-12 * moments.max_element();
            assert!(
                (smallest - moments.min_element()).abs() < tolerance,
                "{moments}"
            );
            assert!(
                (largest - moments.max_element()).abs() < tolerance,
                "{moments}"
            );
        }
    }

    #[test]
    fn the_floor_leaves_ordinary_bodies_and_lifts_only_a_needle() {
        let brick = turned(DVec3::new(1.0, 4.0, 4.5));
        assert_eq!(with_inertia_floor(brick), brick);
        let needle = turned(DVec3::new(1e-9, 1.0, 1.0));
        let [smallest, largest] = principal_extremes(with_inertia_floor(needle));
        assert!((smallest / largest - MIN_INERTIA_RATIO).abs() < 1e-9);
        // The larger moments grow by the lift only, 1e-4 of themselves.
        assert!((largest - 1.0).abs() < 1.01 * MIN_INERTIA_RATIO);
    }
}
