//! What the viewer can ask of the simulation. Commands are applied between two steps, in the
//! order they were sent.

use std::path::PathBuf;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::physics::{BroadPhaseKind, Integrator, Pipeline};

/// The primitive a spawn button creates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum SpawnKind {
    Sphere,
    Box,
    Capsule,
    Cylinder,
    /// A convex hull of random points.
    Hull,
}

impl SpawnKind {
    pub const ALL: [SpawnKind; 5] = [
        SpawnKind::Sphere,
        SpawnKind::Box,
        SpawnKind::Capsule,
        SpawnKind::Cylinder,
        SpawnKind::Hull,
    ];

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
    /// Sets the restitution of every body, and of bodies spawned later.
    SetRestitution(f64),
    /// Sets the friction coefficient of every body, and of bodies spawned later.
    SetFriction(f64),
    /// Sets restitution and friction of the bodies made of the scene's material `name`.
    SetMaterial {
        name: String,
        restitution: f64,
        friction: f64,
    },
    /// Fixed step, s.
    SetDt(f64),
    /// Simulated seconds per wall-clock second.
    SetTimeScale(f64),
    SetIntegrator(Integrator),
    /// The contact pipeline: the soft solver or the report's classic method.
    SetPipeline(Pipeline),
    /// The broad phase: sweep and prune, uniform grid or brute force.
    SetBroadPhase(BroadPhaseKind),
    /// Substeps (soft) or slices (classic) per step.
    SetSubsteps(u32),
    SetSleeping(bool),
    Spawn {
        kind: SpawnKind,
        position: DVec3,
        velocity: DVec3,
    },
    /// An impulse (N·s) at a world point on body `body` (index into the snapshot's bodies).
    ApplyImpulse {
        body: usize,
        impulse: DVec3,
        point: DVec3,
    },
    /// Takes body `body` (index into the snapshot's bodies) out of the world; what rested on
    /// it wakes and falls.
    RemoveBody {
        body: usize,
    },
    /// Writes the world, with the scene name and hidden bodies, to a file (see `SavedWorld`).
    SaveWorld(PathBuf),
    /// Replaces the world by one saved with `SaveWorld`.
    LoadWorld(PathBuf),
    /// Writes the scene and every command applied so far, for replay (see `recording`).
    SaveRecording(PathBuf),
    /// Ends the thread.
    Quit,
}
