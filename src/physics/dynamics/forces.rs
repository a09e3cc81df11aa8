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

    /// True when every parameter is a finite number and coefficients are not negative
    /// (a negative drag would pump energy in).
    pub fn is_valid(&self) -> bool {
        match *self {
            EnvironmentForce::Gravity { acceleration } => acceleration.is_finite(),
            EnvironmentForce::LinearDrag { coefficient }
            | EnvironmentForce::QuadraticDrag { coefficient } => {
                coefficient.is_finite() && coefficient >= 0.0
            }
            EnvironmentForce::Wind {
                velocity,
                coefficient,
            } => velocity.is_finite() && coefficient.is_finite() && coefficient >= 0.0,
        }
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
