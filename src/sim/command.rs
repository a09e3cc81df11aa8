//! What the viewer can ask of the simulation. Commands are applied between two steps, in the
//! order they were sent.

use std::path::PathBuf;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::physics::{BroadPhaseKind, EnvironmentForce, Integrator, JointDrives, Pipeline};

/// The primitive a spawn button creates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum SpawnKind {
    /// Radius 0.3 m.
    Sphere,
    /// A cube of half-extent 0.3 m.
    Box,
    /// Half-height 0.3 m, radius 0.2 m.
    Capsule,
    /// Half-height 0.25 m, radius 0.3 m.
    Cylinder,
    /// A convex hull of 14 random points 0.2 to 0.35 m from its origin.
    Hull,
}

impl SpawnKind {
    /// Every kind, in the order the panel shows its buttons.
    pub const ALL: [SpawnKind; 5] = [
        SpawnKind::Sphere,
        SpawnKind::Box,
        SpawnKind::Capsule,
        SpawnKind::Cylinder,
        SpawnKind::Hull,
    ];

    /// Lower-case name, given to the bodies spawned as this kind.
    pub fn name(self) -> &'static str {
        match self {
            SpawnKind::Sphere => "sphere",
            SpawnKind::Box => "box",
            SpawnKind::Capsule => "capsule",
            SpawnKind::Cylinder => "cylinder",
            SpawnKind::Hull => "hull",
        }
    }
}

/// One request to the simulation. Recordings store them as RON (`SetDt(0.005)`,
/// `Spawn(kind: Box, position: (0, 5, 0), velocity: (0, 0, 0))`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Command {
    /// Stops or restarts the clock; stepping once still works while paused.
    SetPaused(bool),
    /// Advances exactly one fixed step (meant for use while paused).
    StepOnce,
    /// Rebuilds the current scene from scratch.
    Reset,
    /// Replaces the world by a built-in scene (see `scenes::scene_names`) or a scene file.
    LoadScene(String),
    /// Replaces every gravity field by this acceleration (m/s²).
    SetGravity(DVec3),
    /// Sets the restitution of every body, and of bodies spawned later; clamped to [0, 1].
    SetRestitution(f64),
    /// Sets the friction coefficient of every body, and of bodies spawned later; negative
    /// values become 0.
    SetFriction(f64),
    /// Sets restitution and friction of the bodies made of the scene's material `name`.
    /// Ignored when either value is not finite.
    SetMaterial {
        /// A key of the scene's `materials`, `own: BODY` for an inline one, or `spawned`.
        name: String,
        /// Clamped to [0, 1].
        restitution: f64,
        /// Negative values become 0.
        friction: f64,
    },
    /// Fixed step, s, in [`DT_RANGE`]; refused outside it (see `Command::check`).
    SetDt(f64),
    /// Simulated seconds per wall-clock second; clamped to [0, 10], 0 stopping the clock.
    SetTimeScale(f64),
    /// How orientations are advanced from one step to the next.
    SetIntegrator(Integrator),
    /// The contact pipeline: the soft solver or the report's classic method.
    SetPipeline(Pipeline),
    /// The broad phase: sweep and prune, uniform grid or brute force.
    SetBroadPhase(BroadPhaseKind),
    /// Substeps (soft) or slices (classic) per step; clamped to [1, 64].
    SetSubsteps(u32),
    /// Lets bodies at rest fall asleep (true) or keeps every body awake (false).
    SetSleeping(bool),
    /// Adds a body of the current restitution and friction; refused once the world holds
    /// `MAX_BODIES`.
    Spawn {
        /// Which primitive.
        kind: SpawnKind,
        /// Where its shape's origin goes, m; if its bounding box would overlap another
        /// body's, it is raised to 2 cm above the highest one over the same footprint.
        position: DVec3,
        /// m/s
        velocity: DVec3,
    },
    /// An impulse (N·s) at a world point on body `body` (index into the snapshot's bodies).
    /// Ignored for static bodies, out-of-range indices and non-finite vectors.
    ApplyImpulse {
        /// Index into the snapshot's bodies.
        body: usize,
        /// N·s, world axes.
        impulse: DVec3,
        /// Where it acts, world coordinates, m.
        point: DVec3,
    },
    /// Takes body `body` (index into the snapshot's bodies) out of the world; what rested on
    /// it wakes and falls.
    RemoveBody {
        /// Index into the snapshot's bodies.
        body: usize,
    },
    /// Changes the motor, servo and spring of joint `joint` (index into the world's joints,
    /// as `JointId`); refused, with a message, where `World::set_joint_drives` refuses.
    SetJointDrives {
        /// Index into the world's joints.
        joint: u32,
        /// What drives it from now on.
        drives: JointDrives,
    },
    /// Writes the world, with the scene name and hidden bodies, to a file (see `SavedWorld`).
    SaveWorld(PathBuf),
    /// Replaces the world by one saved with `SaveWorld`.
    LoadWorld(PathBuf),
    /// Writes the scene and every command applied so far, for replay (see `recording`).
    SaveRecording(PathBuf),
    /// Ends the simulation: the thread returns, or the browser's loop stops stepping.
    Quit,
}

/// Fixed steps a simulation accepts, s: the panel's rates (30 to 1000 Hz) lie well inside;
/// beyond them the fixed-dt loop cannot keep up or the integrators lose their accuracy.
pub const DT_RANGE: (f64, f64) = (1e-4, 0.05);

impl Command {
    /// The variant's name, for messages about a command.
    pub fn name(&self) -> &'static str {
        match self {
            Command::SetPaused(_) => "SetPaused",
            Command::StepOnce => "StepOnce",
            Command::Reset => "Reset",
            Command::LoadScene(_) => "LoadScene",
            Command::SetGravity(_) => "SetGravity",
            Command::SetRestitution(_) => "SetRestitution",
            Command::SetFriction(_) => "SetFriction",
            Command::SetMaterial { .. } => "SetMaterial",
            Command::SetDt(_) => "SetDt",
            Command::SetTimeScale(_) => "SetTimeScale",
            Command::SetIntegrator(_) => "SetIntegrator",
            Command::SetPipeline(_) => "SetPipeline",
            Command::SetBroadPhase(_) => "SetBroadPhase",
            Command::SetSubsteps(_) => "SetSubsteps",
            Command::SetSleeping(_) => "SetSleeping",
            Command::Spawn { .. } => "Spawn",
            Command::ApplyImpulse { .. } => "ApplyImpulse",
            Command::RemoveBody { .. } => "RemoveBody",
            Command::SetJointDrives { .. } => "SetJointDrives",
            Command::SaveWorld(_) => "SaveWorld",
            Command::LoadWorld(_) => "LoadWorld",
            Command::SaveRecording(_) => "SaveRecording",
            Command::Quit => "Quit",
        }
    }

    /// Refuses the values no control of the viewer sends and the simulation cannot run with:
    /// a dt outside [`DT_RANGE`] (NaN would freeze the world), a gravity beyond
    /// `MAX_GRAVITY` or not finite, or a non-finite time scale, material coefficient or
    /// spawn. `SetMaterial` and `ApplyImpulse` ignore non-finite values themselves, so are not
    /// refused here.
    pub fn check(&self) -> Result<(), String> {
        let finite = |field: &str, ok: bool, value: &dyn std::fmt::Display| {
            if ok {
                Ok(())
            } else {
                Err(format!("{field} must be finite, got {value}"))
            }
        };
        match self {
            Command::SetDt(dt) => {
                let (min, max) = DT_RANGE;
                if (min..=max).contains(dt) {
                    Ok(())
                } else {
                    Err(format!("dt must lie in [{min}, {max}] s, got {dt}"))
                }
            }
            Command::SetGravity(g) => EnvironmentForce::Gravity { acceleration: *g }
                .validate()
                .map_err(|e| format!("gravity {}", e.reason)),
            Command::SetTimeScale(s) => finite("time scale", s.is_finite(), s),
            Command::SetRestitution(e) => finite("restitution", e.is_finite(), e),
            Command::SetFriction(mu) => finite("friction", mu.is_finite(), mu),
            Command::Spawn {
                position, velocity, ..
            } => {
                finite("position", position.is_finite(), position)?;
                finite("velocity", velocity.is_finite(), velocity)
            }
            _ => Ok(()),
        }
    }

    /// The file the command reads or writes, if it names one: a saved world, a recording, or
    /// a scene file (a built-in scene is no file). A recording from elsewhere runs these only
    /// when the user allows it (see `FileCommands`).
    pub fn file_named(&self) -> Option<String> {
        match self {
            Command::SaveWorld(path) | Command::LoadWorld(path) | Command::SaveRecording(path) => {
                Some(path.display().to_string())
            }
            Command::LoadScene(name) if crate::scene::find_builtin(name).is_none() => {
                Some(name.clone())
            }
            _ => None,
        }
    }
}
