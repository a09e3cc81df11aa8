//! Environmental forces: a list the world owns and the user edits while the simulation runs.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::physics::dynamics::body::RigidBody;

/// Standard gravity, m/s².
pub const STANDARD_GRAVITY: f64 = 9.81;

/// A force field acting on every dynamic body through its centre of mass, v being the
/// body's velocity; a world applies each of its `World::forces` at every (sub)step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum EnvironmentForce {
    /// A uniform field: F = m g. Zero gives weightlessness, (0, −1.62, 0) the Moon.
    Gravity {
        /// g, world, m/s².
        acceleration: DVec3,
    },
    /// Viscous drag F = −k v, k in N·s/m.
    LinearDrag {
        /// k, N·s/m, ≥ 0.
        coefficient: f64,
    },
    /// Aerodynamic drag F = −c |v| v, c in N·s²/m².
    QuadraticDrag {
        /// c, N·s²/m², ≥ 0.
        coefficient: f64,
    },
    /// Air moving at `velocity` drags bodies along: F = k (w − v), k in N·s/m.
    Wind {
        /// w, the air's velocity, world, m/s.
        velocity: DVec3,
        /// k, N·s/m, ≥ 0.
        coefficient: f64,
    },
}

impl EnvironmentForce {
    /// Gravity of `STANDARD_GRAVITY` along −y.
    pub fn earth_gravity() -> Self {
        EnvironmentForce::Gravity {
            acceleration: DVec3::new(0.0, -STANDARD_GRAVITY, 0.0),
        }
    }

    /// The force this field exerts on `body` through its centre of mass.
    pub fn force_on(&self, body: &RigidBody) -> DVec3 {
        match *self {
            EnvironmentForce::Gravity { acceleration } => acceleration * body.mass(),
            EnvironmentForce::LinearDrag { coefficient } => -coefficient * body.velocity(),
            EnvironmentForce::QuadraticDrag { coefficient } => {
                let v = body.velocity();
                -coefficient * v.length() * v
            }
            EnvironmentForce::Wind {
                velocity,
                coefficient,
            } => coefficient * (velocity - body.velocity()),
        }
    }

    /// True when `validate` accepts the force.
    pub fn is_valid(&self) -> bool {
        self.validate().is_ok()
    }

    /// Every parameter finite and within its limit: |g| ≤ `MAX_GRAVITY`, |w| ≤
    /// `MAX_WIND_SPEED`, coefficients in [0, `MAX_DRAG_COEFFICIENT`] (a negative drag would
    /// pump energy in). Scenes, snapshots and recordings are checked with it.
    pub fn validate(&self) -> Result<(), ForceError> {
        match *self {
            EnvironmentForce::Gravity { acceleration } => {
                at_most("acceleration", acceleration.length(), MAX_GRAVITY, " m/s²")
            }
            EnvironmentForce::LinearDrag { coefficient }
            | EnvironmentForce::QuadraticDrag { coefficient } => drag_coefficient(coefficient),
            EnvironmentForce::Wind {
                velocity,
                coefficient,
            } => {
                at_most("velocity", velocity.length(), MAX_WIND_SPEED, " m/s")?;
                drag_coefficient(coefficient)
            }
        }
    }
}

/// Largest gravity a world takes, m/s² (about 1 000 g): at 1e12 m/s² bodies cross a metre
/// in a substep and tunnel, and at 1e308 the momenta overflow.
pub const MAX_GRAVITY: f64 = 1e4;

/// Largest wind speed, m/s: thirty times the speed of sound, far beyond any weather; 1e300
/// made momenta overflow.
pub const MAX_WIND_SPEED: f64 = 1e4;

/// Largest drag or wind coefficient, in N·s/m (N·s²/m² for quadratic drag); 1e9 ended in
/// NaN on bodies of a kilogram. Drag is applied explicitly, so it is stable only while
/// k·h/m < 2 (h the substep, m the body's mass): below the limit a body light enough still
/// diverges, and is then isolated and reported as any non-finite body.
pub const MAX_DRAG_COEFFICIENT: f64 = 1e6;

/// Why `EnvironmentForce::validate` refused a force: the field as the force spells it.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("{field} {reason}")]
pub struct ForceError {
    /// `acceleration`, `velocity` or `coefficient`.
    pub field: &'static str,
    /// What is wrong, with the value found.
    pub reason: String,
}

/// A magnitude that is finite and at most `limit`.
fn at_most(field: &'static str, value: f64, limit: f64, unit: &str) -> Result<(), ForceError> {
    if value.is_finite() && value <= limit {
        return Ok(());
    }
    let reason = format!("must be finite and at most {limit:e}{unit} in magnitude, got {value:e}");
    Err(ForceError { field, reason })
}

fn drag_coefficient(coefficient: f64) -> Result<(), ForceError> {
    if coefficient >= 0.0 {
        at_most("coefficient", coefficient, MAX_DRAG_COEFFICIENT, "")
    } else {
        let reason = format!("must be finite and not negative, got {coefficient}");
        Err(ForceError {
            field: "coefficient",
            reason,
        })
    }
}

/// Adds every environmental force to the body's accumulator. Static bodies feel nothing.
pub fn apply_environment(forces: &[EnvironmentForce], body: &mut RigidBody) {
    if !body.is_dynamic() {
        return;
    }
    let total: DVec3 = forces.iter().map(|force| force.force_on(body)).sum();
    body.apply_force(total);
}

/// Potential energy of `body` in the uniform gravity fields of `forces` (zero at the origin).
pub fn potential_energy(forces: &[EnvironmentForce], body: &RigidBody) -> f64 {
    if !body.is_dynamic() {
        return 0.0;
    }
    forces
        .iter()
        .map(|force| match force {
            EnvironmentForce::Gravity { acceleration } => {
                -body.mass() * acceleration.dot(body.position)
            }
            _ => 0.0,
        })
        .sum()
}
