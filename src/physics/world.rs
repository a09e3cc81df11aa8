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

use crate::physics::collision::broad_phase::{BodyPair, BroadPhaseKind, Proxy, SplitBroadPhase};
use crate::physics::collision::closing_speed::Clusters;
use crate::physics::collision::contact::ContactManifold;
use crate::physics::collision::contact_cache::ContactCache;
use crate::physics::collision::manifold_memory::ManifoldMemory;
use crate::physics::collision::narrow_phase::{self, NarrowScratch};
use crate::physics::dynamics::awake_set::AwakeSet;
use crate::physics::dynamics::body::{BodyDesc, BodyError, BodyId, Motion, RigidBody};
use crate::physics::dynamics::containment;
use crate::physics::dynamics::forces::{self, EnvironmentForce};
use crate::physics::dynamics::integrate::{self, Integrator};
use crate::physics::dynamics::islands::{self, IslandScratch, SleepSettings};
use crate::physics::dynamics::slots::Slots;
use crate::physics::geometry::aabb::Aabb;
use crate::physics::joints::desc::JointId;
use crate::physics::joints::joint::Joint;
use crate::physics::snapshot::{SNAPSHOT_FORMAT, SnapshotError, WorldSnapshot};
use crate::physics::solver::classic::{self, ClassicContext, ClassicReport, ClassicSettings};
use crate::physics::solver::soft::{
    self, ContactInput, SoftScratch, SoftSolverSettings, StepContext,
};
use crate::physics::stage_times::{StageTimes, timed};

/// How a world steps: `World::settings`, which may be changed between steps.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct WorldSettings {
    /// How the bodies' poses are advanced, in either pipeline.
    pub integrator: Integrator,
    /// Which contact pipeline runs the steps.
    pub pipeline: Pipeline,
    /// How candidate pairs are found; a change takes effect at the next step.
    pub broad_phase: BroadPhaseKind,
    /// Settings of the `soft` pipeline.
    pub solver: SoftSolverSettings,
    /// Settings of the `classic` pipeline.
    pub classic: ClassicSettings,
    /// When islands of bodies fall asleep.
    pub sleep: SleepSettings,
    /// Most candidate pairs a step keeps (`DEFAULT_MAX_PAIRS` unless changed). Every
    /// per-pair list of a step (pairs, manifolds, contacts) is bounded by it; beyond it the
    /// extra pairs get no contacts that step and `World::pair_budget_fault` says so.
    pub max_pairs: usize,
}

/// `WorldSettings::max_pairs` by default: 10 pairs per body at `MAX_BODIES`, as many as a
/// dense pile has. A step over it peaks near 2.6 GB (about 2.6 kB per pair across the
/// narrow phase's and solver's lists); 10 000 spheres created at one point make 5·10⁷
/// pairs and once asked the narrow phase alone for 18 GB.
pub const DEFAULT_MAX_PAIRS: usize = 1_000_000;

impl Default for WorldSettings {
    fn default() -> Self {
        WorldSettings {
            integrator: Integrator::default(),
            pipeline: Pipeline::default(),
            broad_phase: BroadPhaseKind::default(),
            solver: SoftSolverSettings::default(),
            classic: ClassicSettings::default(),
            sleep: SleepSettings::default(),
            max_pairs: DEFAULT_MAX_PAIRS,
        }
    }
}

/// How contacts are handled; switchable between steps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Pipeline {
    /// Substepped soft-constraint solver with warm starting and friction (see `solver::soft`).
    #[default]
    Soft,
    /// The report's method: time-ordered impacts, bisection rewind, Newton impulses
    /// (see `classic`).
    Classic,
}

/// A simulated world: its rigid bodies, the environmental forces on them and the settings,
/// advanced by `step(dt)`.
///
/// A world starts empty and without gravity (`World::default()` or `World::new(settings)`);
/// push onto `forces` (`EnvironmentForce::earth_gravity()`) and edit `settings` freely between
/// steps. Bodies come from a [`BodyDesc`] through `add_body`, which returns the body's
/// [`BodyId`]; an id stays valid until `remove_body` takes its body out, after which it is
/// refused (`get_body` answers None) even once a new body has taken the slot. Read
/// bodies with `body` and `bodies`, change them through `body_mut` (the next step looks at
/// a changed body again). Joints come from a [`JointDesc`](crate::physics::JointDesc)
/// through `add_joint`; kinematic bodies move by `set_kinematic_velocity` or
/// `set_kinematic_target`, and `set_motion` switches a body between dynamic, kinematic and
/// static.
///
/// Each `step(dt)`, dt in s, runs the broad phase, the narrow phase, islands and sleep, then
/// the chosen contact pipeline (`Pipeline`) with the forces and integration; a negative dt
/// runs the bodies backwards without contacts. A body whose state stops being finite is
/// isolated and listed in `faults`; a step that finds more candidate pairs than
/// `settings.max_pairs` keeps that many and is reported by `pair_budget_fault`. The last step's results are read with
/// `contacts`, `max_penetration`, `awake_count`, `pair_count`, `stage_times` and
/// `classic_report`; `totals` sums energy and momentum. `ray_cast` and `shape_cast` query
/// the bodies, and `to_snapshot` / `from_snapshot` save a world and continue it exactly.
#[derive(Clone, Debug)]
pub struct World {
    bodies: Vec<RigidBody>,
    /// The generation of each body slot, and the removed slots to reuse.
    slots: Slots,
    broad_phase: SplitBroadPhase,
    /// Broad-phase proxies kept between steps (see `narrow_phase::update_proxies`).
    proxies: Vec<Proxy>,
    /// The awake bodies, and the bodies touched since the last step: what a step visits.
    awake_set: AwakeSet,
    /// Everyone was woken since sleeping was last switched off.
    woken_for_no_sleep: bool,
    manifolds: Vec<ContactManifold>,
    /// The last step's manifolds in their bodies' frames, carried while pairs barely move.
    manifold_memory: ManifoldMemory,
    /// The narrow phase's lists, kept between steps (see `narrow_phase::find_manifolds`).
    narrow_scratch: NarrowScratch,
    /// The bodies of this step's pairs, grouped by them (see `closing_speed`).
    clusters: Clusters,
    contact_cache: ContactCache,
    /// The soft solver's contacts and buffers, kept so that a step does not allocate them
    /// again.
    solver_inputs: Vec<ContactInput>,
    soft_scratch: SoftScratch,
    island_scratch: IslandScratch,
    /// The force list as the last step saw it: an edit wakes every body.
    forces_seen: Vec<EnvironmentForce>,
    awake: usize,
    /// Pairs the last forward step's broad phase handed to the narrow phase (the list is
    /// kept so that a step reuses its memory).
    pairs: Vec<BodyPair>,
    classic_report: ClassicReport,
    /// The users' forces and torques, held over the classic pipeline's slices.
    classic_loads: Vec<[DVec3; 2]>,
    stage_times: StageTimes,
    /// Whether steps measure `stage_times`.
    stage_timing: bool,
    /// Environmental forces, applied to every dynamic body each step. Edit freely.
    pub forces: Vec<EnvironmentForce>,
    /// How the world steps; edit freely between steps.
    pub settings: WorldSettings,
    time: f64,
    steps: u64,
    faults: Vec<Fault>,
    /// The last step that went over `settings.max_pairs`, if any did.
    pair_budget_fault: Option<PairBudgetFault>,
    /// By `JointId`; None where a joint was removed.
    joints: Vec<Option<Joint>>,
    /// What the joints tie together, derived from `joints` (see `joints::JointLinks`).
    joint_links: JointLinks,
    /// The joints the last step broke and took out.
    broken_joints: Vec<JointId>,
}

mod joints;
mod kinematic;
use joints::JointLinks;
pub use kinematic::MotionError;

impl Default for World {
    fn default() -> Self {
        World::new(WorldSettings::default())
    }
}

/// Longest step `World::step` takes, s: far beyond any stable contact step, short enough
/// that a typo (a dt in milliseconds) is caught.
pub const MAX_STEP: f64 = 1.0;

/// Most body slots a world holds (a removed body's slot is reused by a later body).
/// Scenes share the limit: beyond it a count is almost certainly a typo or a runaway loop,
/// and building the bodies would only exhaust memory.
pub const MAX_BODIES: usize = 100_000;
const _: () = assert!(MAX_BODIES <= 1 << BodyId::INDEX_BITS);

/// Why `World::add_body` refused a body; the world is left as it was.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum AddBodyError {
    /// The description failed `BodyDesc::validate`.
    #[error(transparent)]
    Invalid(#[from] BodyError),
    /// The world already holds `MAX_BODIES` bodies, and no removed body's slot is free.
    #[error("the world already holds {MAX_BODIES} bodies, the most it takes")]
    TooManyBodies,
}

/// Why `World::remove_body` refused; each holds the id's number.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum RemoveError {
    /// No body has this id.
    #[error("there is no body {0}")]
    NoSuchBody(u32),
    /// The body was removed before.
    #[error("body {0} was already removed")]
    AlreadyRemoved(u32),
}

/// Why `World::try_step` refused a step; the world is left as it was.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum StepError {
    /// The `dt` given, s, is not finite or is longer than `MAX_STEP` either way.
    #[error("dt must be finite and at most {MAX_STEP} s either way, got {0}")]
    BadDt(f64),
    /// The classic pipeline has no joints: a world holding any steps with `Pipeline::Soft`.
    #[error("the classic pipeline does not solve joints; this world holds {0}")]
    JointsNeedSoft(usize),
    /// The classic pipeline has no kinematic bodies: a world holding any steps with
    /// `Pipeline::Soft`.
    #[error("the classic pipeline does not move kinematic bodies; this world holds {0}")]
    KinematicNeedsSoft(usize),
    /// A negative dt runs bodies backwards without contacts or joints: a world holding
    /// joints is not run backwards.
    #[error("a world with joints is not run backwards; this one holds {0}")]
    JointsNotBackwards(usize),
}

/// A body whose state stopped being finite, and when. The body is isolated the same step.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fault {
    /// The isolated body.
    pub body: BodyId,
    /// Its name.
    pub name: String,
    /// The step that caught it, counted from 0 (`World::step_count` before that step).
    pub step: u64,
    /// Simulated time at the start of that step, s.
    pub time: f64,
    /// Why it was isolated (faults saved before reasons were kept read as `NonFinite`).
    #[serde(default)]
    pub reason: FaultReason,
}

/// Why a body was isolated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum FaultReason {
    /// Its state, force or torque was NaN or infinite.
    #[default]
    NonFinite,
    /// It was about to touch another body with a speed or spin beyond `MAX_CONTACT_SPEED`,
    /// or a coordinate beyond `MAX_CONTACT_POSITION`, where the contact's arithmetic would
    /// overflow or create energy.
    BeyondContactRange,
}

impl std::fmt::Display for FaultReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FaultReason::NonFinite => f.write_str("its state, force or torque is not finite"),
            FaultReason::BeyondContactRange => write!(
                f,
                "it met another body at a speed or spin over {:e} (or a coordinate over {:e}), \
                 beyond what a contact can compute",
                containment::MAX_CONTACT_SPEED,
                containment::MAX_CONTACT_POSITION
            ),
        }
    }
}

/// A step whose broad phase found more pairs than `WorldSettings::max_pairs`: it kept that
/// many and left the others without contacts, so bodies of those pairs may pass through
/// each other that step.
#[derive(Clone, Debug, PartialEq)]
pub struct PairBudgetFault {
    /// The last step that went over the budget, counted from 0.
    pub step: u64,
    /// Simulated time at the start of that step, s.
    pub time: f64,
    /// The budget it went over, pairs.
    pub max_pairs: usize,
    /// Steps so far that went over the budget.
    pub steps_over: u64,
}

/// Totals over all dynamic bodies, for summaries and conservation checks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldTotals {
    /// Σ (½ m v² + ½ ω·A), J.
    pub kinetic_energy: f64,
    /// In the gravity fields of `World::forces`, zero at the origin, J.
    pub potential_energy: f64,
    /// Σ L, world, kg·m/s.
    pub linear_momentum: DVec3,
    /// About the world origin: Σ (C × L + A), world, kg·m²/s.
    pub angular_momentum: DVec3,
}

impl World {
    /// An empty world with these settings: no bodies, no forces (not even gravity), time 0.
    pub fn new(settings: WorldSettings) -> Self {
        World {
            bodies: Vec::new(),
            slots: Slots::default(),
            broad_phase: SplitBroadPhase::new(settings.broad_phase),
            proxies: Vec::new(),
            awake_set: AwakeSet::default(),
            woken_for_no_sleep: false,
            manifolds: Vec::new(),
            manifold_memory: ManifoldMemory::default(),
            narrow_scratch: NarrowScratch::default(),
            clusters: Clusters::default(),
            contact_cache: ContactCache::default(),
            solver_inputs: Vec::new(),
            soft_scratch: SoftScratch::default(),
            island_scratch: IslandScratch::default(),
            forces_seen: Vec::new(),
            awake: 0,
            pairs: Vec::new(),
            classic_report: ClassicReport::default(),
            classic_loads: Vec::new(),
            stage_times: StageTimes::default(),
            stage_timing: false,
            forces: Vec::new(),
            settings,
            time: 0.0,
            steps: 0,
            faults: Vec::new(),
            pair_budget_fault: None,
            joints: Vec::new(),
            joint_links: JointLinks::default(),
            broken_joints: Vec::new(),
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
            touched: self.awake_set.touched().to_vec(),
            contact_cache: self.contact_cache.clone(),
            manifold_memory: self.manifold_memory.clone(),
            awake: self.awake,
            faults: self.faults.clone(),
            joints: self.joints.clone(),
            generations: self.slots.generations().to_vec(),
        }
    }

    /// A world that continues exactly where the snapshot's world was. The snapshot is checked
    /// first; `file` names it in errors.
    pub fn from_snapshot(snapshot: WorldSnapshot, file: &str) -> Result<World, SnapshotError> {
        snapshot.check(file)?;
        Ok(World {
            slots: Slots::restored(snapshot.generations, &snapshot.bodies),
            bodies: snapshot.bodies,
            proxies: snapshot.proxies,
            awake_set: AwakeSet::with_touched(snapshot.touched),
            contact_cache: snapshot.contact_cache,
            manifold_memory: snapshot.manifold_memory,
            forces_seen: snapshot.forces_seen,
            awake: snapshot.awake,
            forces: snapshot.forces,
            time: snapshot.time,
            steps: snapshot.steps,
            faults: snapshot.faults,
            joint_links: JointLinks::of(&snapshot.joints),
            joints: snapshot.joints,
            ..World::new(snapshot.settings)
        })
    }

    /// Adds a body; the description is validated first. It takes the lowest slot a removed
    /// body left, if any, under a new generation (see `BodyId`); a world whose `MAX_BODIES`
    /// slots are all held refuses it.
    pub fn add_body(&mut self, desc: BodyDesc) -> Result<BodyId, AddBodyError> {
        let body = RigidBody::from_desc(&desc)?;
        let id = match self.slots.reuse() {
            Some(id) => {
                self.bodies[id.index()] = body;
                // The removed body's warm-start impulses must not start the new one.
                self.contact_cache.forget_body(id.index());
                id
            }
            None if self.bodies.len() >= MAX_BODIES => return Err(AddBodyError::TooManyBodies),
            None => {
                self.bodies.push(body);
                self.slots.push()
            }
        };
        self.awake_set.touch(id.index());
        Ok(id)
    }

    /// Takes a body out: it no longer moves, feels forces or touches anything, and every
    /// sleeping body whose broad-phase box touched its box wakes up, so that what rested on
    /// it falls. Its joints are removed with it. Its id is refused from then on, and its
    /// slot goes to a later body.
    pub fn remove_body(&mut self, id: BodyId) -> Result<(), RemoveError> {
        let index = id.index();
        match self.bodies.get(index).map(|b| b.motion) {
            None => return Err(RemoveError::NoSuchBody(id.0)),
            // An older generation: the body it named was removed (its slot may hold another).
            Some(_) if !self.slots.is_current(id) => {
                return Err(RemoveError::AlreadyRemoved(id.0));
            }
            Some(Motion::Removed) => return Err(RemoveError::AlreadyRemoved(id.0)),
            Some(_) => {}
        }
        self.slots.release(index);
        self.wake_neighbours(index);
        self.remove_joints_of(index);
        let body = &mut self.bodies[index];
        body.motion = Motion::Removed;
        body.sleeping = false;
        body.linear_momentum = DVec3::ZERO;
        body.angular_momentum = DVec3::ZERO;
        self.awake_set.touch(index);
        Ok(())
    }

    /// Wakes every sleeping body whose broad-phase box touches that of body `index` (its last
    /// box: the body itself may no longer be finite).
    fn wake_neighbours(&mut self, index: usize) {
        let reach = self
            .proxies
            .get(index)
            .map_or_else(|| Aabb::of_body(&self.bodies[index]), |p| p.aabb);
        for (other, proxy) in self.bodies.iter_mut().zip(&self.proxies) {
            if other.sleeping && proxy.aabb.overlaps(&reach) {
                other.wake();
            }
        }
    }

    /// The body `id`.
    ///
    /// # Panics
    /// If the world has no such body: an id from another world, or of a removed body (whose
    /// slot may hold another by now); `get_body` does not.
    pub fn body(&self, id: BodyId) -> &RigidBody {
        self.get_body(id)
            .unwrap_or_else(|| panic!("no body {id:?} in this world (removed, or never added)"))
    }

    /// The body `id`, or None if the world has no such body (or `id` names a removed one).
    pub fn get_body(&self, id: BodyId) -> Option<&RigidBody> {
        self.slots.is_current(id).then(|| &self.bodies[id.index()])
    }

    /// `body_mut`, or None if the world has no such body (or `id` names a removed one).
    pub fn get_body_mut(&mut self, id: BodyId) -> Option<&mut RigidBody> {
        if !self.slots.is_current(id) {
            return None;
        }
        self.awake_set.touch(id.index());
        Some(&mut self.bodies[id.index()])
    }

    /// Mutable access; the next step looks at the body again (its box, whether it is awake,
    /// whether its state is finite).
    ///
    /// # Panics
    /// As `body`; `get_body_mut` does not.
    pub fn body_mut(&mut self, id: BodyId) -> &mut RigidBody {
        self.get_body_mut(id)
            .unwrap_or_else(|| panic!("no body {id:?} in this world (removed, or never added)"))
    }

    /// The id the body in slot `index` (of `bodies`) answers to, if the slot exists.
    pub fn id_at(&self, index: usize) -> Option<BodyId> {
        (index < self.bodies.len()).then(|| self.slots.current(index))
    }

    /// Every body slot, indexed by `BodyId::index`; isolated and removed bodies included
    /// (see `RigidBody::motion`) until a new body takes a removed one's slot.
    pub fn bodies(&self) -> &[RigidBody] {
        &self.bodies
    }

    /// The current id of every slot, in order (a removed body's slot answers to the id its
    /// next body will get).
    pub fn body_ids(&self) -> impl Iterator<Item = BodyId> + use<> {
        // Gathered, so that the caller may edit the world while walking them.
        let ids: Vec<BodyId> = (0..self.bodies.len())
            .map(|index| self.slots.current(index))
            .collect();
        ids.into_iter()
    }

    /// Simulated time, s.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Steps taken, backward ones included (refused ones are not).
    pub fn step_count(&self) -> u64 {
        self.steps
    }

    /// Advances the world by `dt` seconds; a negative `dt` runs it backwards. A step that
    /// `try_step` refuses (a bad `dt`; joints on the classic pipeline or backwards) leaves
    /// the world as it is.
    pub fn step(&mut self, dt: f64) {
        let _ = self.try_step(dt);
    }

    /// `step`, or an error for a `dt` that is not finite or longer than `MAX_STEP` either way
    /// (one NaN step would otherwise isolate every body), and for a world with joints or
    /// kinematic bodies on the classic pipeline, which would otherwise move its bodies as if
    /// they were not joined, or leave kinematic bodies in place.
    pub fn try_step(&mut self, dt: f64) -> Result<(), StepError> {
        if !(dt.is_finite() && dt.abs() <= MAX_STEP) {
            return Err(StepError::BadDt(dt));
        }
        let joints = self.joint_count();
        if joints > 0 && self.settings.pipeline == Pipeline::Classic {
            return Err(StepError::JointsNeedSoft(joints));
        }
        if joints > 0 && dt < 0.0 {
            return Err(StepError::JointsNotBackwards(joints));
        }
        if self.settings.pipeline == Pipeline::Classic {
            let kinematic = self.bodies.iter().filter(|b| b.is_kinematic()).count();
            if kinematic > 0 {
                return Err(StepError::KinematicNeedsSoft(kinematic));
            }
        }
        self.advance(dt);
        Ok(())
    }

    /// One step: a call per stage, each timed when `set_stage_timing` asked for it.
    fn advance(&mut self, dt: f64) {
        let on = self.stage_timing;
        let mut times = StageTimes::default();
        let touched = self.awake_set.take_touched();
        // A non-finite user force or state is caught before any contact can spread it.
        timed(on, &mut times.checks, || self.isolate_non_finite(&touched));
        if dt >= 0.0 {
            // Before the broad phase: the margins must see the velocities a target sets.
            self.aim_kinematic_targets(dt);
            timed(on, &mut times.broad_phase, || {
                self.wake_on_user_input(&touched);
                self.broad_phase(dt, &touched);
            });
            timed(on, &mut times.checks, || {
                self.isolate_beyond_range(&touched)
            });
            timed(on, &mut times.narrow_phase, || {
                self.narrow_phase(dt, &touched)
            });
            timed(on, &mut times.islands, || self.islands_and_sleep());
            let mut solve_and_integrate = 0.0;
            times.integrate = timed(on, &mut solve_and_integrate, || self.solve(dt));
            self.arrive_at_kinematic_targets(dt);
            self.break_overloaded_joints();
            times.solve = (solve_and_integrate - times.integrate).max(0.0);
            timed(on, &mut times.islands, || self.add_quiet_time(dt));
        } else {
            timed(on, &mut times.solve, || self.run_backwards(dt, &touched));
        }
        timed(on, &mut times.checks, || self.isolate_broken_awake_bodies());
        self.stage_times = times;
        self.time += dt;
        self.steps += 1;
    }

    /// The contact manifolds of the broad phase's pairs, new or updated from the last step's.
    fn narrow_phase(&mut self, dt: f64, touched: &[u32]) {
        self.manifold_memory.forget(touched);
        self.clusters.measure(&self.bodies, &self.pairs);
        narrow_phase::find_manifolds(
            &self.bodies,
            &self.pairs,
            &self.clusters,
            dt,
            &mut self.manifold_memory,
            &mut self.narrow_scratch,
            &mut self.manifolds,
        );
    }

    /// The awake bodies' quiet times, from the speeds the step left them with.
    fn add_quiet_time(&mut self, dt: f64) {
        if self.settings.sleep.enabled {
            let awake = self.awake_set.awake(&self.bodies);
            islands::add_quiet_time(&mut self.bodies, awake, dt, &self.settings.sleep);
            let driven = (self.joints.iter().flatten())
                .filter(|joint| joint.is_driven())
                .flat_map(|joint| [joint.body_a.index(), joint.body_b.index()]);
            islands::hold_driven_awake(&mut self.bodies, driven, &self.settings.sleep);
        }
    }

    /// Islands fall asleep or wake; the manifolds between two idle bodies leave the solver.
    fn islands_and_sleep(&mut self) {
        self.update_sleep();
        let bodies = &self.bodies;
        self.manifolds
            .retain(|m| bodies[m.body_a.index()].is_awake() || bodies[m.body_b.index()].is_awake());
    }

    /// Forces, integration and contacts, by the chosen pipeline; returns the seconds spent
    /// integrating when the pipeline measures them apart (`soft`), else 0.
    fn solve(&mut self, dt: f64) -> f64 {
        match self.settings.pipeline {
            Pipeline::Soft => self.solve_soft(dt),
            Pipeline::Classic => {
                self.solve_classic(dt);
                0.0
            }
        }
    }

    /// After the step: the awake bodies whose state went non-finite are isolated. Only the
    /// broken ones are listed (none, and nothing allocated, in a healthy step): isolating a
    /// body edits the awake set.
    fn isolate_broken_awake_bodies(&mut self) {
        let bodies = &self.bodies;
        let broken: Vec<u32> = (self.awake_set.awake(bodies).iter().copied())
            .filter(|&index| needs_isolating(&bodies[index as usize]))
            .collect();
        self.isolate_non_finite(&broken);
    }

    /// Where the last step's time went; all zeros unless `set_stage_timing(true)` was called
    /// before it.
    pub fn stage_times(&self) -> StageTimes {
        self.stage_times
    }

    /// Whether the following steps measure their stages' wall time. Off by default: it
    /// reads the clock several times per substep, which small scenes notice.
    pub fn set_stage_timing(&mut self, on: bool) {
        self.stage_timing = on;
    }

    /// Islands of the awake bodies fall asleep or wake (see `islands`). With sleeping off,
    /// every body is woken once.
    fn update_sleep(&mut self) {
        if !self.settings.sleep.enabled {
            if !self.woken_for_no_sleep {
                self.bodies
                    .iter_mut()
                    .filter(|b| b.sleeping)
                    .for_each(RigidBody::wake);
                self.awake_set.invalidate();
                self.woken_for_no_sleep = true;
            }
        } else {
            self.woken_for_no_sleep = false;
            let awake = self.awake_set.awake(&self.bodies);
            let sleep = &self.settings.sleep;
            let scratch = &mut self.island_scratch;
            let links = self.joint_links.links();
            if islands::update(
                &mut self.bodies,
                awake,
                &self.manifolds,
                links,
                sleep,
                scratch,
            ) {
                self.awake_set.invalidate();
            }
        }
        self.awake = self.awake_set.awake(&self.bodies).len();
    }

    /// Counters of the last step when the classic pipeline ran it.
    pub fn classic_report(&self) -> ClassicReport {
        self.classic_report
    }

    /// The report's pipeline; its touching contacts replace the speculative ones for display.
    fn solve_classic(&mut self, dt: f64) {
        let ctx = ClassicContext {
            forces: &self.forces,
            integrator: self.settings.integrator,
            settings: &self.settings.classic,
            dt,
        };
        let loads = &mut self.classic_loads;
        let (report, touching) = classic::step(&mut self.bodies, &self.pairs, &ctx, loads);
        self.classic_report = report;
        self.manifolds = touching;
        self.manifold_memory.clear();
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

    /// Candidate pairs of the last forward step's broad phase (overlapping fattened boxes).
    pub fn pair_count(&self) -> usize {
        self.pairs.len()
    }

    /// A changed force list wakes every body; a force a user put on a sleeping body wakes it.
    /// Forces the user put on a static body are dropped (nothing ever clears them otherwise).
    fn wake_on_user_input(&mut self, touched: &[u32]) {
        // Before the first step there is nothing to compare with: bodies start awake anyway,
        // and one put to sleep by hand stays asleep.
        let forces_changed = self.forces != self.forces_seen;
        if forces_changed {
            self.forces_seen = self.forces.clone();
        }
        if forces_changed && self.steps > 0 {
            self.bodies
                .iter_mut()
                .filter(|b| b.sleeping)
                .for_each(RigidBody::wake);
            self.awake_set.invalidate();
        }
        for &index in touched {
            let body = &mut self.bodies[index as usize];
            let pushed = body.force != DVec3::ZERO || body.torque != DVec3::ZERO;
            if body.sleeping && pushed {
                body.wake();
            }
            if !body.is_dynamic() {
                body.clear_accumulators();
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

    /// Proxies of the awake and touched bodies are refreshed; idle ones are kept, and only
    /// when some body fell asleep, woke or was touched are the idle boxes looked at again.
    /// The pairs go to `self.pairs`.
    fn broad_phase(&mut self, dt: f64, touched: &[u32]) {
        if self.broad_phase.kind() != self.settings.broad_phase {
            self.broad_phase = SplitBroadPhase::new(self.settings.broad_phase);
        }
        let awake = self.awake_set.awake(&self.bodies);
        let refresh = awake.iter().chain(touched).map(|&i| i as usize);
        narrow_phase::update_proxies(&self.bodies, dt, &mut self.proxies, refresh);
        let idle_changed = self.awake_set.take_rebuilt();
        if idle_changed {
            // Bodies that fell asleep keep their box but stop initiating pairs.
            for (proxy, body) in self.proxies.iter_mut().zip(&self.bodies) {
                proxy.active = body.is_awake();
            }
        }
        let awake = self.awake_set.awake(&self.bodies);
        let limit = self.settings.max_pairs;
        let (proxies, pairs) = (&self.proxies, &mut self.pairs);
        let over = (self.broad_phase).fill_pairs_within(proxies, awake, idle_changed, pairs, limit);
        self.joint_links.drop_unjoined_pairs(&mut self.pairs);
        if over {
            let steps_over = self.pair_budget_fault.as_ref().map_or(0, |f| f.steps_over);
            self.pair_budget_fault = Some(PairBudgetFault {
                step: self.steps,
                time: self.time,
                max_pairs: limit,
                steps_over: steps_over + 1,
            });
        }
    }

    /// The soft pipeline's step: forces, integration and contacts together, in substeps (see
    /// `solver::soft`); returns the seconds it spent integrating.
    fn solve_soft(&mut self, dt: f64) -> f64 {
        let mut inputs = std::mem::take(&mut self.solver_inputs);
        self.contact_cache
            .solver_inputs(&self.bodies, &self.manifolds, &mut inputs);
        let ctx = StepContext {
            forces: &self.forces,
            integrator: self.settings.integrator,
            settings: &self.settings.solver,
            dt,
            timed: self.stage_timing,
        };
        let awake = self.awake_set.awake(&self.bodies);
        let step = soft::step(
            &mut self.bodies,
            awake,
            &inputs,
            &mut self.joints,
            &ctx,
            &mut self.soft_scratch,
        );
        self.contact_cache
            .store(&self.manifolds, self.soft_scratch.impulses());
        self.solver_inputs = inputs;
        step.integrate_seconds
    }

    /// Bodies isolated so far because their state went non-finite (NaN or infinity).
    pub fn faults(&self) -> &[Fault] {
        &self.faults
    }

    /// The last step whose broad phase found more pairs than `settings.max_pairs`, with the
    /// number of such steps; None while no step did.
    pub fn pair_budget_fault(&self) -> Option<&PairBudgetFault> {
        self.pair_budget_fault.as_ref()
    }

    /// The forward substeps undone in reverse order: without contacts and with forces that do
    /// not depend on position, this retraces the forward motion exactly.
    fn run_backwards(&mut self, dt: f64, touched: &[u32]) {
        self.manifolds.clear();
        let substeps = self.settings.solver.substeps.max(1);
        let h = dt / substeps as f64;
        let awake = self.awake_set.awake(&self.bodies);
        for &index in awake {
            let body = &mut self.bodies[index as usize];
            let (force, torque) = (body.force, body.torque);
            for _ in 0..substeps {
                body.force = force;
                body.torque = torque;
                forces::apply_environment(&self.forces, body);
                integrate::integrate_body(body, h, self.settings.integrator);
            }
            body.clear_accumulators();
        }
        // No broad phase ran: the next forward step still has to look at these.
        for &index in touched {
            self.awake_set.touch(index as usize);
        }
    }

    /// Diagnostics stage: a body whose state is no longer finite is isolated before anything
    /// else can read it, so NaN never spreads to other bodies or to the world totals. Only
    /// the listed bodies can have changed: the ones the user touched, or the broken awake
    /// ones.
    fn isolate_non_finite(&mut self, bodies: &[u32]) {
        for &index in bodies {
            if needs_isolating(&self.bodies[index as usize]) {
                self.isolate(index, FaultReason::NonFinite);
            }
        }
    }

    /// Before the narrow phase: a body beyond contact range loses its pairs, and is
    /// isolated if it had any, so that no contact computes with its numbers; the bodies it
    /// would have touched go on untouched.
    fn isolate_beyond_range(&mut self, touched: &[u32]) {
        let awake = self.awake_set.awake(&self.bodies);
        let far = containment::bodies_beyond_range(&self.bodies, awake, touched);
        if far.is_empty() {
            return;
        }
        for index in containment::drop_pairs_of(&mut self.pairs, &far) {
            self.isolate(index, FaultReason::BeyondContactRange);
        }
    }

    /// Takes body `index` out of the simulation and lists it in `faults`.
    fn isolate(&mut self, index: u32, reason: FaultReason) {
        // What rested on it must not stay asleep in mid-air, as on a removal.
        self.wake_neighbours(index as usize);
        let body = &mut self.bodies[index as usize];
        body.motion = Motion::Isolated;
        self.faults.push(Fault {
            body: self.slots.current(index as usize),
            name: body.name.clone(),
            step: self.steps,
            time: self.time,
            reason,
        });
        self.awake_set.touch(index as usize);
    }

    /// Energy and momentum summed over the dynamic bodies (isolated and removed ones left
    /// out).
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

/// A body that still takes part in the simulation with a state, force or torque that is no
/// longer finite.
fn needs_isolating(body: &RigidBody) -> bool {
    let finite = body.is_finite() && body.force.is_finite() && body.torque.is_finite();
    body.motion.takes_part() && !finite
}
