//! The simulation thread: it owns the `World`, steps it at a fixed dt and publishes
//! snapshots; the viewer only sends commands and reads the newest snapshot, so a slow frame
//! never slows the physics and a slow step never blocks a frame.
//!
//! Reading order: `scenes` (what worlds exist) → `command` (what the user can ask) →
//! `recording` and `saved_world` (runs and worlds kept in files) →
//! `simulation` (the world plus its settings, stepped synchronously) → `snapshot` (what is
//! published) → `fixed_step` (the fixed-dt clock) → `thread` (that clock on its own thread)
//! and `frame_loop` (the same clock driven by the browser's frames).

pub mod command;
pub mod fixed_step;
pub mod frame_loop;
pub mod recording;
pub mod saved_world;
pub mod scenes;
pub mod simulation;
pub mod snapshot;
pub mod spawn;
#[cfg(not(target_arch = "wasm32"))]
pub mod thread;
pub mod world_bounds;

pub use command::{Command, SpawnKind};
pub use frame_loop::FrameLoop;
pub use recording::{
    FileCommands, MAX_RECORDING_TICKS, RecordedCommand, Recording, RecordingError,
};
pub use saved_world::SavedWorld;
pub use scenes::{CameraHint, DEFAULT_SCENE, SceneSetup, scene_names};
pub use simulation::Simulation;
pub use snapshot::{BodyState, Counters, HistorySample, LineSegment, ShapeTable, Snapshot};
#[cfg(not(target_arch = "wasm32"))]
pub use thread::SimHandle;

/// What the viewer drives: the simulation thread on native targets; in the browser, which
/// gives the page one thread that must never block, the loop its animation frames pump.
#[cfg(not(target_arch = "wasm32"))]
pub type Driver = SimHandle;
/// What the viewer drives: in the browser, the loop its animation frames pump.
#[cfg(target_arch = "wasm32")]
pub type Driver = FrameLoop;
