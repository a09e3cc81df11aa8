//! The world: bodies, environmental forces and settings, advanced by `step(dt)`.
//!
//! A step reads as its stages: forces → integrate → diagnostics (non-finite bodies isolated).
//!
//! ```
//! use glam::DVec3;
//! use rigid::physics::{BodyDesc, EnvironmentForce, Shape, World};
//!
//! let mut world = World::default();
//! world.forces.push(EnvironmentForce::earth_gravity());
//! let ball = world.add_body(BodyDesc::dynamic(Shape::sphere(0.5)).at(DVec3::Y * 10.0)).unwrap();
//! for _ in 0..60 {
//!     world.step(1.0 / 60.0);
//! }
//! assert!(world.body(ball).position.y < 10.0 - 4.0);
//! ```

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::physics::body::{BodyDesc, BodyError, BodyId, Motion, RigidBody};
use crate::physics::forces::{self, EnvironmentForce};
use crate::physics::integrate::{self, Integrator};

#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct WorldSettings {
    pub integrator: Integrator,
}

#[derive(Clone, Debug, Default)]
pub struct World {
    bodies: Vec<RigidBody>,
    /// Environmental forces, applied to every dynamic body each step. Edit freely.
    pub forces: Vec<EnvironmentForce>,
    pub settings: WorldSettings,
    time: f64,
    steps: u64,
    faults: Vec<Fault>,
}

/// A body whose state stopped being finite, and when. The body is isolated the same step.
#[derive(Clone, Debug, PartialEq)]
pub struct Fault {
    pub body: BodyId,
    pub name: String,
    pub step: u64,
    pub time: f64,
}

/// Totals over all dynamic bodies, for summaries and conservation checks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldTotals {
    pub kinetic_energy: f64,
    pub potential_energy: f64,
    pub linear_momentum: DVec3,
    /// About the world origin: Σ (C × L + A).
    pub angular_momentum: DVec3,
}

impl World {
    pub fn new(settings: WorldSettings) -> Self {
        World {
            settings,
            ..World::default()
        }
    }

    /// Adds a body; the description is validated first.
    pub fn add_body(&mut self, desc: BodyDesc) -> Result<BodyId, BodyError> {
        let body = RigidBody::from_desc(&desc)?;
        let id = BodyId(self.bodies.len() as u32);
        self.bodies.push(body);
        Ok(id)
    }

    pub fn body(&self, id: BodyId) -> &RigidBody {
        &self.bodies[id.index()]
    }

    pub fn body_mut(&mut self, id: BodyId) -> &mut RigidBody {
        &mut self.bodies[id.index()]
    }

    pub fn bodies(&self) -> &[RigidBody] {
        &self.bodies
    }

    pub fn body_ids(&self) -> impl Iterator<Item = BodyId> + use<> {
        (0..self.bodies.len() as u32).map(BodyId)
    }

    /// Simulated time, s.
    pub fn time(&self) -> f64 {
        self.time
    }

    pub fn step_count(&self) -> u64 {
        self.steps
    }

    /// Advances the world by `dt` seconds; a negative `dt` runs it backwards.
    pub fn step(&mut self, dt: f64) {
        self.apply_forces();
        self.integrate(dt);
        self.isolate_non_finite();
        self.time += dt;
        self.steps += 1;
    }

    /// Bodies isolated so far because their state went non-finite (NaN or infinity).
    pub fn faults(&self) -> &[Fault] {
        &self.faults
    }

    fn apply_forces(&mut self) {
        for body in &mut self.bodies {
            forces::apply_environment(&self.forces, body);
        }
    }

    fn integrate(&mut self, dt: f64) {
        for body in &mut self.bodies {
            integrate::integrate_body(body, dt, self.settings.integrator);
            body.clear_accumulators();
        }
    }

    /// Diagnostics stage: a body whose state is no longer finite is isolated before anything
    /// else can read it, so NaN never spreads to other bodies or to the world totals.
    fn isolate_non_finite(&mut self) {
        for (index, body) in self.bodies.iter_mut().enumerate() {
            if body.motion != Motion::Isolated && !body.is_finite() {
                body.motion = Motion::Isolated;
                self.faults.push(Fault {
                    body: BodyId(index as u32),
                    name: body.name.clone(),
                    step: self.steps,
                    time: self.time,
                });
            }
        }
    }

    pub fn totals(&self) -> WorldTotals {
        let dynamic = self.bodies.iter().filter(|b| b.is_dynamic());
        let mut totals = WorldTotals {
            kinetic_energy: 0.0,
            potential_energy: 0.0,
            linear_momentum: DVec3::ZERO,
            angular_momentum: DVec3::ZERO,
        };
        for body in dynamic {
            totals.kinetic_energy += body.kinetic_energy();
            totals.potential_energy += forces::potential_energy(&self.forces, body);
            totals.linear_momentum += body.linear_momentum;
            totals.angular_momentum +=
                body.position.cross(body.linear_momentum) + body.angular_momentum;
        }
        totals
    }
}
