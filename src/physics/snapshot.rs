//! Saving and restoring a whole world: the bodies, the forces and settings, and the state the
//! next step reads (warm-start impulses, remembered manifolds, cached broad-phase boxes, sleep timers, the force list
//! the last step saw). A world restored from a snapshot continues bit for bit as if it had
//! never stopped; the broad phase's own bookkeeping is only a cache and is rebuilt.
//!
//! Snapshots are RON text. Loading one checks it as strictly as a scene file: a file that does
//! not parse, whose bodies are not finite, not valid shapes, of materials a scene refuses, of
//! mass properties their motion cannot have, or refer to bodies that do not exist, whose
//! forces are not finite or drag negatively, or whose step count would wrap, gives an error
//! naming the file, the body and the field instead of a world that misbehaves later.

use std::path::Path;

use glam::{DMat3, DQuat, DVec3};
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::physics::collision::broad_phase::{BroadPhaseKind, Proxy};
use crate::physics::collision::contact_cache::ContactCache;
use crate::physics::collision::manifold_memory::ManifoldMemory;
use crate::physics::dynamics::body::{BodyId, MAX_BODY_ENERGY, Motion, RigidBody};
use crate::physics::dynamics::forces::EnvironmentForce;
use crate::physics::joints::joint::Joint;
use crate::physics::world::{Fault, MAX_BODIES, WorldSettings};

/// Raised when the layout of `WorldSnapshot` changes.
pub const SNAPSHOT_FORMAT: u32 = 2;

/// Everything a `World` is made of, as plain data.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldSnapshot {
    /// The `SNAPSHOT_FORMAT` it was written with; any other is refused.
    pub format: u32,
    /// Simulated time, s (`World::time`).
    pub time: f64,
    /// Steps taken (`World::step_count`).
    pub steps: u64,
    /// `World::settings`.
    pub settings: WorldSettings,
    /// `World::forces`.
    pub forces: Vec<EnvironmentForce>,
    /// The force list the last step saw: an edit since then wakes every body.
    pub forces_seen: Vec<EnvironmentForce>,
    /// Every body by id, isolated and removed ones included.
    pub bodies: Vec<RigidBody>,
    /// Broad-phase boxes kept between steps, by body.
    pub proxies: Vec<Proxy>,
    /// Bodies added or edited since the last step, which the next step looks at again.
    pub touched: Vec<u32>,
    /// The impulses each contact ended the last step with, for warm starting.
    pub contact_cache: ContactCache,
    /// The last step's manifolds in their bodies' frames (see `manifold_memory`).
    pub manifold_memory: ManifoldMemory,
    /// Dynamic bodies awake in the last step (`World::awake_count`).
    pub awake: usize,
    /// Bodies isolated so far (`World::faults`).
    pub faults: Vec<Fault>,
    /// The joints by id, None where one was removed (absent in snapshots from before
    /// joints: none).
    #[serde(default)]
    pub joints: Vec<Option<Joint>>,
    /// Per body slot, the generation of its id (see `BodyId`); empty in snapshots written
    /// before ids had generations.
    #[serde(default)]
    pub generations: Vec<u32>,
}

/// Why a snapshot could not be read, written or used. `file` names the snapshot as the
/// caller did (a path, or the name given to `from_ron`).
#[derive(Debug, Error, PartialEq)]
pub enum SnapshotError {
    /// The file could not be read or written, or its text does not parse.
    #[error("{file}: {message}")]
    Unreadable {
        /// The snapshot's name.
        file: String,
        /// The reader's, writer's or parser's error.
        message: String,
    },
    /// Written with another `SNAPSHOT_FORMAT`.
    #[error("{file}: format {found}, this build reads format {SNAPSHOT_FORMAT}")]
    Format {
        /// The snapshot's name.
        file: String,
        /// The format the snapshot has.
        found: u32,
    },
    /// A body the engine cannot take: an invalid shape or material, a state that is not
    /// finite, an orientation that is not a rotation, mass properties that do not fit its
    /// motion (a dynamic body without a positive inverse mass and a symmetric positive
    /// definite inverse inertia, a static one with any) or a world inertia that is not
    /// R I⁻¹ Rᵀ.
    #[error("{file}: body {index} ('{name}') field '{field}': {message}")]
    Body {
        /// The snapshot's name.
        file: String,
        /// The body's index (its id).
        index: usize,
        /// The body's name.
        name: String,
        /// The offending field of `RigidBody`: `material.friction`, `inv_inertia_local`.
        field: String,
        /// What is wrong with it.
        message: String,
    },
    /// Parts that do not fit together (a reference to a missing body, too many bodies) or
    /// settings out of range.
    #[error("{file}: {message}")]
    Inconsistent {
        /// The snapshot's name.
        file: String,
        /// What is wrong.
        message: String,
    },
}

impl WorldSnapshot {
    /// The snapshot as pretty-printed RON text.
    pub fn to_ron(&self) -> String {
        let config = ron::ser::PrettyConfig::new().depth_limit(3);
        ron::ser::to_string_pretty(self, config).expect("a snapshot is plain data")
    }

    /// Parses and checks snapshot text; `file` names it in errors.
    pub fn from_ron(text: &str, file: &str) -> Result<WorldSnapshot, SnapshotError> {
        let snapshot: WorldSnapshot =
            ron::from_str(text).map_err(|e| SnapshotError::Unreadable {
                file: file.to_string(),
                message: e.to_string(),
            })?;
        snapshot.check(file)?;
        Ok(snapshot)
    }

    /// Writes `to_ron` to `path` (see `output_file::write_atomically`: a failed write leaves
    /// the file that was there); a failed write is `Unreadable`.
    pub fn save(&self, path: &Path) -> Result<(), SnapshotError> {
        crate::output_file::write_atomically(path, &self.to_ron()).map_err(|e| {
            SnapshotError::Unreadable {
                file: path.display().to_string(),
                message: e.to_string(),
            }
        })
    }

    /// Reads, parses and checks the snapshot file at `path`.
    pub fn load(path: &Path) -> Result<WorldSnapshot, SnapshotError> {
        let file = path.display().to_string();
        let text = crate::input_file::read_text(path).map_err(|e| SnapshotError::Unreadable {
            file: file.clone(),
            message: e.to_string(),
        })?;
        WorldSnapshot::from_ron(&text, &file)
    }

    /// What the engine relies on and a hand-edited file could break.
    pub fn check(&self, file: &str) -> Result<(), SnapshotError> {
        if self.format != SNAPSHOT_FORMAT {
            return Err(SnapshotError::Format {
                file: file.to_string(),
                found: self.format,
            });
        }
        let inconsistent = |message: String| SnapshotError::Inconsistent {
            file: file.to_string(),
            message,
        };
        let count = self.bodies.len();
        if count > MAX_BODIES {
            return Err(inconsistent(format!(
                "{count} bodies, more than the {MAX_BODIES} a world holds"
            )));
        }
        for (index, body) in self.bodies.iter().enumerate() {
            check_body(body).map_err(|(field, message)| SnapshotError::Body {
                file: file.to_string(),
                index,
                name: body.name.clone(),
                field: field.to_string(),
                message,
            })?;
        }
        if self.steps > MAX_STEPS {
            return Err(inconsistent(format!(
                "steps must be at most {MAX_STEPS} (2^53), got {}",
                self.steps
            )));
        }
        if self.proxies.len() > count {
            return Err(inconsistent(format!(
                "bodies: {count} listed, but the broad phase holds {} (a body is missing)",
                self.proxies.len()
            )));
        }
        check_generations(&self.generations, &self.bodies).map_err(inconsistent)?;
        if self.touched.iter().any(|&i| i as usize >= count) {
            return Err(inconsistent("touched names a missing body".into()));
        }
        if self
            .contact_cache
            .max_body_index()
            .is_some_and(|i| i >= count)
        {
            return Err(inconsistent(
                "the contact cache names a missing body".into(),
            ));
        }
        self.manifold_memory
            .check(&self.bodies)
            .map_err(inconsistent)?;
        if let Some(fault) = self.faults.iter().find(|f| f.body.index() >= count) {
            return Err(inconsistent(format!(
                "fault on missing body {}",
                fault.body.0
            )));
        }
        if !self.time.is_finite() {
            return Err(inconsistent("time is not finite".into()));
        }
        self.check_joints().map_err(inconsistent)?;
        check_settings(&self.settings).map_err(|m| inconsistent(format!("settings: {m}")))?;
        // The loader of scenes refuses the same: a negative drag pumps energy in.
        for (index, force) in self.forces.iter().enumerate() {
            force
                .validate()
                .map_err(|e| inconsistent(format!("forces[{index}].{e}")))?;
        }
        Ok(())
    }
}

impl WorldSnapshot {
    /// Each joint joins two different bodies that take part (both may have been made static
    /// since: the solver leaves such a joint alone), with numbers a joint can have
    /// (`Joint::check`).
    fn check_joints(&self) -> Result<(), String> {
        for (index, joint) in self.joints.iter().enumerate() {
            let Some(joint) = joint else { continue };
            // Current: the generation of its slot (0 in a snapshot without generations).
            let current = |id: BodyId| {
                let generation = self.generations.get(id.index()).copied().unwrap_or(0);
                id.generation() == generation
            };
            let body = |id: BodyId| {
                (self.bodies.get(id.index())).filter(|b| current(id) && b.motion.takes_part())
            };
            if body(joint.body_a).is_none() || body(joint.body_b).is_none() {
                return Err(format!("joints[{index}] names a missing or removed body"));
            }
            if joint.body_a == joint.body_b {
                let id = joint.body_a.0;
                return Err(format!("joints[{index}] joins body {id} to itself"));
            }
            joint.check().map_err(|m| format!("joints[{index}]: {m}"))?;
        }
        Ok(())
    }
}

/// One generation per body, none past `BodyId::MAX_GENERATION`, or none at all (an older
/// snapshot).
fn check_generations(generations: &[u32], bodies: &[RigidBody]) -> Result<(), String> {
    if !generations.is_empty() && generations.len() != bodies.len() {
        return Err(format!(
            "generations: {} listed for {} bodies",
            generations.len(),
            bodies.len()
        ));
    }
    match generations.iter().position(|&g| g > BodyId::MAX_GENERATION) {
        Some(index) => Err(format!(
            "generations[{index}] must be at most {}, got {}",
            BodyId::MAX_GENERATION,
            generations[index]
        )),
        None => Ok(()),
    }
}

/// Most substeps, slices, iterations and events per step a snapshot may ask for: beyond
/// these a single step takes seconds, which a hand-edited file should not be able to cause.
const MAX_SUBSTEPS: u32 = 64;
const MAX_ITERATIONS: u32 = 1000;

/// Settings the solvers can run with: counts in range, rates and speeds finite and
/// non-negative (positive where they divide).
fn check_settings(settings: &WorldSettings) -> Result<(), String> {
    let soft = &settings.solver;
    let classic = &settings.classic;
    let sleep = &settings.sleep;
    let counts = [
        ("solver.substeps", soft.substeps, MAX_SUBSTEPS),
        ("classic.substeps", classic.substeps, MAX_SUBSTEPS),
        ("classic.iterations", classic.iterations, MAX_ITERATIONS),
        ("classic.max_events", classic.max_events, MAX_ITERATIONS),
    ];
    for (field, value, max) in counts {
        if !(1..=max).contains(&value) {
            return Err(format!("{field} must lie in [1, {max}], got {value}"));
        }
    }
    let cell_size = match settings.broad_phase {
        BroadPhaseKind::UniformGrid { cell_size } => cell_size,
        _ => 1.0,
    };
    let positive = [
        ("solver.contact_hertz", soft.contact_hertz),
        ("solver.joint_hertz", soft.joint_hertz),
        ("classic.theta", classic.theta),
        ("broad_phase.cell_size", cell_size),
    ];
    for (field, value) in positive {
        if !(value.is_finite() && value > 0.0) {
            return Err(format!("{field} must be positive, got {value}"));
        }
    }
    let non_negative = [
        ("solver.damping_ratio", soft.damping_ratio),
        ("solver.joint_damping_ratio", soft.joint_damping_ratio),
        ("solver.max_push_out", soft.max_push_out),
        ("solver.deep_overlap", soft.deep_overlap),
        ("solver.restitution_threshold", soft.restitution_threshold),
        ("classic.resting_speed", classic.resting_speed),
        ("sleep.sleep_speed", sleep.sleep_speed),
        ("sleep.time_to_sleep", sleep.time_to_sleep),
    ];
    for (field, value) in non_negative {
        if !(value.is_finite() && value >= 0.0) {
            return Err(format!(
                "{field} must be finite and non-negative, got {value}"
            ));
        }
    }
    Ok(())
}

/// How far RᵀR may stray from the identity: the integrators keep it within 1e-15, so this
/// only catches hand edits.
const ORTHONORMAL_TOLERANCE: f64 = 1e-6;

fn is_rotation(r: DMat3) -> bool {
    let worst = largest_entry(r.transpose() * r - DMat3::IDENTITY);
    worst <= ORTHONORMAL_TOLERANCE && r.determinant() > 0.0
}

/// Most steps a snapshot may have taken: the count must leave room to step on without
/// wrapping, and no run comes near it (2^53 steps of 1 µs are 285 years).
pub const MAX_STEPS: u64 = 1 << 53;

/// A body the solver can take, as strict as a scene's: a valid shape and material, and
/// (unless it was isolated for going non-finite or removed) a finite state and the mass
/// properties its motion implies. Errors are (field, what is wrong).
fn check_body(body: &RigidBody) -> Result<(), (&'static str, String)> {
    body.shape
        .validate()
        .map_err(|e| ("shape", e.to_string()))?;
    if !body.motion.takes_part() {
        return Ok(());
    }
    body.material
        .validate(&body.name)
        .map_err(|e| (e.field(), e.reason()))?;
    let vectors = [
        ("position", body.position),
        ("linear_momentum", body.linear_momentum),
        ("angular_momentum", body.angular_momentum),
        ("local_center", body.local_center),
        ("force", body.force),
        ("torque", body.torque),
    ];
    for (field, value) in vectors {
        if !value.is_finite() {
            return Err((field, format!("state is not finite: {value}")));
        }
    }
    if !body.orientation.is_finite() {
        return Err(("orientation", "state is not finite".into()));
    }
    if !is_rotation(body.orientation) {
        return Err(("orientation", "is not a rotation matrix".into()));
    }
    if !(body.quiet_time.is_finite() && body.quiet_time >= 0.0) {
        return Err((
            "quiet_time",
            format!("must be finite and non-negative, got {}", body.quiet_time),
        ));
    }
    check_mass_properties(body)?;
    // After the mass check: the energies read the velocities the inverse mass gives.
    if let Some(field) = body.energy_beyond_limit(["linear_momentum", "angular_momentum"]) {
        let message = format!("gives a kinetic energy or momentum above {MAX_BODY_ENERGY:e}");
        return Err((field, message));
    }
    Ok(())
}

/// A kinematic body's velocities and target are finite (a unit rotation); any other body has
/// none.
fn check_kinematic_state(body: &RigidBody) -> Result<(), (&'static str, String)> {
    let target = body.kinematic_target;
    if body.is_kinematic() {
        if !(body.kinematic_velocity.is_finite() && body.kinematic_spin.is_finite()) {
            return Err(("kinematic_velocity", "must be finite".into()));
        }
        let unit = |q: DQuat| q.is_finite() && (q.length() - 1.0).abs() < 1e-9;
        if target.is_some_and(|(p, q)| !p.is_finite() || !unit(q)) {
            let message = "must be a finite position and a unit rotation".into();
            return Err(("kinematic_target", message));
        }
    } else if body.kinematic_velocity != DVec3::ZERO
        || body.kinematic_spin != DVec3::ZERO
        || target.is_some()
    {
        return Err(("kinematic_velocity", "only a kinematic body has one".into()));
    }
    Ok(())
}

/// A dynamic body has a positive inverse mass and a symmetric positive definite inverse
/// inertia; a static one has neither (as `RigidBody::from_desc` makes them). Either way the
/// world inverse inertia must be R I⁻¹ Rᵀ, which the solvers read without recomputing.
fn check_mass_properties(body: &RigidBody) -> Result<(), (&'static str, String)> {
    let local = body.inv_inertia_local;
    check_kinematic_state(body)?;
    if matches!(body.motion, Motion::Static | Motion::Kinematic) {
        let kind = if body.is_kinematic() {
            "kinematic"
        } else {
            "static"
        };
        if body.inv_mass != 0.0 {
            let message = format!("must be 0 on a {kind} body, got {}", body.inv_mass);
            return Err(("inv_mass", message));
        }
        if local != DMat3::ZERO || body.inv_inertia_world != DMat3::ZERO {
            return Err((
                "inv_inertia_local",
                format!("must be zero on a {kind} body"),
            ));
        }
        if body.linear_momentum != DVec3::ZERO || body.angular_momentum != DVec3::ZERO {
            return Err(("linear_momentum", format!("must be zero on a {kind} body")));
        }
        return Ok(());
    }
    if !(body.inv_mass.is_finite() && body.inv_mass > 0.0) {
        return Err((
            "inv_mass",
            format!(
                "must be positive and finite on a dynamic body, got {}",
                body.inv_mass
            ),
        ));
    }
    if !(local.is_finite() && is_symmetric_positive_definite(local)) {
        return Err((
            "inv_inertia_local",
            format!("must be symmetric positive definite, got {local}"),
        ));
    }
    let expected = body.orientation * local * body.orientation.transpose();
    if !close(body.inv_inertia_world, expected) {
        return Err((
            "inv_inertia_world",
            format!(
                "must be R I⁻¹ Rᵀ = {expected}, got {}",
                body.inv_inertia_world
            ),
        ));
    }
    Ok(())
}

fn columns(m: DMat3) -> [glam::DVec3; 3] {
    [m.x_axis, m.y_axis, m.z_axis]
}

fn largest_entry(m: DMat3) -> f64 {
    columns(m)
        .iter()
        .map(|c| c.abs().max_element())
        .fold(0.0, f64::max)
}

/// Equal up to `ORTHONORMAL_TOLERANCE` relative to the larger entry: rounding of the
/// product, never a hand edit.
fn close(a: DMat3, b: DMat3) -> bool {
    let scale = largest_entry(a).max(largest_entry(b));
    largest_entry(a - b) <= ORTHONORMAL_TOLERANCE * scale
}

/// Sylvester's criterion on a matrix symmetric up to rounding: every leading principal
/// minor positive.
fn is_symmetric_positive_definite(m: DMat3) -> bool {
    let [x, y, _] = columns(m);
    close(m, m.transpose()) && x.x > 0.0 && x.x * y.y - x.y * y.x > 0.0 && m.determinant() > 0.0
}
