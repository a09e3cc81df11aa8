//! The simulation thread: it owns the `World`, steps it at a fixed dt and publishes
//! snapshots; the viewer only sends commands and reads the newest snapshot, so a slow frame
//! never slows the physics and a slow step never blocks a frame.
//!
//! Reading order: `scenes` (what worlds exist) → `command` (what the user can ask) →
//! `recording` and `saved_world` (runs and worlds kept in files) →
//! `simulation` (the world plus its settings, stepped synchronously) → `snapshot` (what is
//! published) → `thread` (the fixed-dt loop around a `Simulation`).

pub mod command;
pub mod recording;
pub mod saved_world;
pub mod scenes;
pub mod simulation;
pub mod snapshot;
pub mod spawn;
pub mod thread;

pub use command::{Command, SpawnKind};
pub use recording::{RecordedCommand, Recording};
pub use saved_world::SavedWorld;
pub use scenes::{CameraHint, DEFAULT_SCENE, SceneSetup, scene_names};
pub use simulation::Simulation;
pub use snapshot::{BodyState, Counters, HistorySample, LineSegment, ShapeTable, Snapshot};
pub use thread::SimHandle;
