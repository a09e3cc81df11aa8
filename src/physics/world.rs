//! The world: bodies, environmental forces and settings, advanced by `step(dt)`.
//!
//! A step reads as its stages: broad phase → narrow phase → solve (forces, integration and
//! contacts, in substeps) → diagnostics (non-finite bodies isolated). A negative dt runs the
//! bodies backwards without contacts (forces and integration only), as the report's rewind
//! needs.
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

use crate::physics::aabb::Aabb;
use crate::physics::body::{BodyDesc, BodyError, BodyId, Motion, RigidBody};
use crate::physics::broad_phase::{BodyPair, BroadPhase, BroadPhaseKind, Proxy};
use crate::physics::classic::{self, ClassicContext, ClassicReport, ClassicSettings};
use crate::physics::contact::ContactManifold;
use crate::physics::contact_cache::ContactCache;
use crate::physics::forces::{self, EnvironmentForce};
use crate::physics::integrate::{self, Integrator};
use crate::physics::islands::{self, SleepSettings};
use crate::physics::narrow_phase;
use crate::physics::snapshot::{SNAPSHOT_FORMAT, SnapshotError, WorldSnapshot};
use crate::physics::soft_solver::{self, SoftSolverSettings, StepContext};

#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct WorldSettings {
    pub integrator: Integrator,
    pub pipeline: Pipeline,
    pub broad_phase: BroadPhaseKind,
    /// Settings of the `soft` pipeline.
    pub solver: SoftSolverSettings,
    /// Settings of the `classic` pipeline.
    pub classic: ClassicSettings,
    pub sleep: SleepSettings,
}

/// How contacts are handled; switchable between steps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Pipeline {
    /// Substepped soft-constraint solver with warm starting and friction (see `soft_solver`).
    #[default]
    Soft,
    /// The report's method: time-ordered impacts, bisection rewind, Newton impulses
    /// (see `classic`).
    Classic,
}

#[derive(Clone, Debug, Default)]
pub struct World {
    bodies: Vec<RigidBody>,
    broad_phase: BroadPhaseState,
    /// Broad-phase proxies kept between steps (see `narrow_phase::update_proxies`), and which
    /// of them must be recomputed because the user may have moved the body.
    proxies: Vec<Proxy>,
    stale_proxies: Vec<bool>,
    manifolds: Vec<ContactManifold>,
    contact_cache: ContactCache,
    /// The force list as the last step saw it: an edit wakes every body.
    forces_seen: Vec<EnvironmentForce>,
    awake: usize,
    classic_report: ClassicReport,
    /// Environmental forces, applied to every dynamic body each step. Edit freely.
    pub forces: Vec<EnvironmentForce>,
    pub settings: WorldSettings,
    time: f64,
    steps: u64,
    faults: Vec<Fault>,
}

/// The broad phase in use, rebuilt when the settings name another kind. Its state is only a
/// cache for incremental updates, so a cloned world starts a fresh one.
struct BroadPhaseState {
    kind: BroadPhaseKind,
    implementation: Box<dyn BroadPhase + Send>,
}

impl BroadPhaseState {
    fn new(kind: BroadPhaseKind) -> Self {
        BroadPhaseState {
            kind,
            implementation: kind.create(),
        }
    }
}

impl Default for BroadPhaseState {
    fn default() -> Self {
        BroadPhaseState::new(BroadPhaseKind::default())
    }
}

impl Clone for BroadPhaseState {
    fn clone(&self) -> Self {
        BroadPhaseState::new(self.kind)
    }
}

impl std::fmt::Debug for BroadPhaseState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "BroadPhaseState({:?})", self.kind)
    }
}

/// Longest step `World::step` takes, s: far beyond any stable contact step, short enough
/// that a typo (a dt in milliseconds) is caught.
pub const MAX_STEP: f64 = 1.0;

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum RemoveError {
    #[error("there is no body {0}")]
    NoSuchBody(u32),
    #[error("body {0} was already removed")]
    AlreadyRemoved(u32),
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum StepError {
    #[error("dt must be finite and at most {MAX_STEP} s either way, got {0}")]
    BadDt(f64),
}

/// A body whose state stopped being finite, and when. The body is isolated the same step.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
            broad_phase: BroadPhaseState::new(settings.broad_phase),
            ..World::default()
        }
    }

    /// The whole world as plain data (see `snapshot`).
    pub fn to_snapshot(&self) -> WorldSnapshot {
        WorldSnapshot {
            format: SNAPSHOT_FORMAT,
            time: self.time,
            steps: self.steps,
            settings: self.settings,
            forces: self.forces.clone(),
            forces_seen: self.forces_seen.clone(),
            bodies: self.bodies.clone(),
            proxies: self.proxies.clone(),
            stale_proxies: self.stale_proxies.clone(),
            contact_cache: self.contact_cache.clone(),
            awake: self.awake,
            faults: self.faults.clone(),
        }
    }

    /// A world that continues exactly where the snapshot's world was. The snapshot is checked
    /// first; `file` names it in errors.
    pub fn from_snapshot(snapshot: WorldSnapshot, file: &str) -> Result<World, SnapshotError> {
        snapshot.check(file)?;
        Ok(World {
            bodies: snapshot.bodies,
            broad_phase: BroadPhaseState::new(snapshot.settings.broad_phase),
            proxies: snapshot.proxies,
            stale_proxies: snapshot.stale_proxies,
            manifolds: Vec::new(),
            contact_cache: snapshot.contact_cache,
            forces_seen: snapshot.forces_seen,
            awake: snapshot.awake,
            classic_report: ClassicReport::default(),
            forces: snapshot.forces,
            settings: snapshot.settings,
            time: snapshot.time,
            steps: snapshot.steps,
            faults: snapshot.faults,
        })
    }

    /// Adds a body; the description is validated first.
    pub fn add_body(&mut self, desc: BodyDesc) -> Result<BodyId, BodyError> {
        let body = RigidBody::from_desc(&desc)?;
        let id = BodyId(self.bodies.len() as u32);
        self.bodies.push(body);
        Ok(id)
    }

    /// Takes a body out: it no longer moves, feels forces or touches anything, and every
    /// sleeping body whose broad-phase box touched its box wakes up, so that what rested on
    /// it falls. Its slot stays (see `Motion::Removed`), so other ids stay valid.
    pub fn remove_body(&mut self, id: BodyId) -> Result<(), RemoveError> {
        let index = id.index();
        match self.bodies.get(index).map(|b| b.motion) {
            None => return Err(RemoveError::NoSuchBody(id.0)),
            Some(Motion::Removed) => return Err(RemoveError::AlreadyRemoved(id.0)),
            Some(_) => {}
        }
        let reach = self
            .proxies
            .get(index)
            .map_or_else(|| Aabb::of_body(&self.bodies[index]), |p| p.aabb);
        for (other, proxy) in self.bodies.iter_mut().zip(&self.proxies) {
            if other.sleeping && proxy.aabb.overlaps(&reach) {
                other.wake();
            }
        }
        let body = &mut self.bodies[index];
        body.motion = Motion::Removed;
        body.sleeping = false;
        body.linear_momentum = DVec3::ZERO;
        body.angular_momentum = DVec3::ZERO;
        if let Some(stale) = self.stale_proxies.get_mut(index) {
            *stale = true;
        }
        Ok(())
    }

    pub fn body(&self, id: BodyId) -> &RigidBody {
        &self.bodies[id.index()]
    }

    /// Mutable access; the body's broad-phase box is recomputed at the next step.
    pub fn body_mut(&mut self, id: BodyId) -> &mut RigidBody {
        if let Some(stale) = self.stale_proxies.get_mut(id.index()) {
            *stale = true;
        }
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

    /// Advances the world by `dt` seconds; a negative `dt` runs it backwards. A `dt` that
    /// `try_step` refuses leaves the world as it is.
    pub fn step(&mut self, dt: f64) {
        let _ = self.try_step(dt);
    }

    /// `step`, or an error for a `dt` that is not finite or longer than `MAX_STEP` either way
    /// (one NaN step would otherwise isolate every body).
    pub fn try_step(&mut self, dt: f64) -> Result<(), StepError> {
        if !(dt.is_finite() && dt.abs() <= MAX_STEP) {
            return Err(StepError::BadDt(dt));
        }
        self.advance(dt);
        Ok(())
    }

    fn advance(&mut self, dt: f64) {
        // A non-finite user force or state is caught before any contact can spread it.
        self.isolate_non_finite();
        if dt >= 0.0 {
            self.wake_on_user_input();
            let pairs = self.broad_phase(dt);
            self.manifolds = narrow_phase::find_manifolds(&self.bodies, &pairs, dt);
            self.awake =
                islands::update(&mut self.bodies, &self.manifolds, dt, &self.settings.sleep);
            let bodies = &self.bodies;
            self.manifolds.retain(|m| {
                bodies[m.body_a.index()].is_awake() || bodies[m.body_b.index()].is_awake()
            });
            match self.settings.pipeline {
                Pipeline::Soft => self.solve(dt),
                Pipeline::Classic => self.solve_classic(&pairs, dt),
            }
        } else {
            self.manifolds.clear();
            self.run_backwards(dt);
        }
        self.isolate_non_finite();
        self.time += dt;
        self.steps += 1;
    }

    /// Counters of the last step when the classic pipeline ran it.
    pub fn classic_report(&self) -> ClassicReport {
        self.classic_report
    }

    /// The report's pipeline; its touching contacts replace the speculative ones for display.
    fn solve_classic(&mut self, pairs: &[BodyPair], dt: f64) {
        let ctx = ClassicContext {
            forces: &self.forces,
            integrator: self.settings.integrator,
            settings: &self.settings.classic,
            dt,
        };
        let (report, touching) = classic::step(&mut self.bodies, pairs, &ctx);
        self.classic_report = report;
        self.manifolds = touching;
        self.contact_cache.clear();
    }

    /// The boxes the broad phase sorted in the last step, by body index: each body's bounds
    /// grown by the speculative margin and by how far it can move in a step.
    pub fn broad_phase_proxies(&self) -> &[Proxy] {
        &self.proxies
    }

    /// Dynamic bodies that were awake in the last step.
    pub fn awake_count(&self) -> usize {
        self.awake
    }

    /// A changed force list, or a force a user put on a sleeping body, wakes it.
    fn wake_on_user_input(&mut self) {
        // Before the first step there is nothing to compare with: bodies start awake anyway,
        // and one put to sleep by hand stays asleep.
        let forces_changed = self.forces != self.forces_seen;
        if forces_changed {
            self.forces_seen = self.forces.clone();
        }
        let forces_changed = forces_changed && self.steps > 0;
        for body in self.bodies.iter_mut().filter(|b| b.sleeping) {
            if forces_changed || body.force != DVec3::ZERO || body.torque != DVec3::ZERO {
                body.wake();
            }
        }
    }

    /// The deepest overlap among the last step's contacts, m (0 when nothing overlaps).
    pub fn max_penetration(&self) -> f64 {
        let deepest = self
            .manifolds
            .iter()
            .map(|m| m.min_separation())
            .fold(0.0, f64::min);
        // 0 − x rather than −x: no negative zero when nothing overlaps.
        0.0 - deepest
    }

    /// The contact manifolds found in the last step.
    pub fn contacts(&self) -> &[ContactManifold] {
        &self.manifolds
    }

    fn broad_phase(&mut self, dt: f64) -> Vec<BodyPair> {
        if self.broad_phase.kind != self.settings.broad_phase {
            self.broad_phase = BroadPhaseState::new(self.settings.broad_phase);
        }
        narrow_phase::update_proxies(&self.bodies, dt, &mut self.proxies, &mut self.stale_proxies);
        self.broad_phase.implementation.find_pairs(&self.proxies)
    }

    /// Forces, integration and contacts together, in substeps (see `soft_solver`).
    fn solve(&mut self, dt: f64) {
        let inputs = self.contact_cache.solver_inputs(&self.manifolds);
        let ctx = StepContext {
            forces: &self.forces,
            integrator: self.settings.integrator,
            settings: &self.settings.solver,
            dt,
        };
        let impulses = soft_solver::step(&mut self.bodies, &inputs, &ctx);
        self.contact_cache.store(&self.manifolds, &impulses);
    }

    /// Bodies isolated so far because their state went non-finite (NaN or infinity).
    pub fn faults(&self) -> &[Fault] {
        &self.faults
    }

    /// The forward substeps undone in reverse order: without contacts and with forces that do
    /// not depend on position, this retraces the forward motion exactly.
    fn run_backwards(&mut self, dt: f64) {
        let substeps = self.settings.solver.substeps.max(1);
        let h = dt / substeps as f64;
        for body in self.bodies.iter_mut().filter(|b| b.is_awake()) {
            let (force, torque) = (body.force, body.torque);
            for _ in 0..substeps {
                body.force = force;
                body.torque = torque;
                forces::apply_environment(&self.forces, body);
                integrate::integrate_body(body, h, self.settings.integrator);
            }
            body.clear_accumulators();
        }
    }

    /// Diagnostics stage: a body whose state is no longer finite is isolated before anything
    /// else can read it, so NaN never spreads to other bodies or to the world totals.
    fn isolate_non_finite(&mut self) {
        for (index, body) in self.bodies.iter_mut().enumerate() {
            let finite = body.is_finite() && body.force.is_finite() && body.torque.is_finite();
            if body.motion.takes_part() && !finite {
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
