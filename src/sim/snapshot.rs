//! What the simulation publishes after each batch of steps: plain single-precision data the
//! renderer and UI read without touching the `World`.

use std::sync::Arc;
use web_time::Instant;

use glam::{Quat, Vec3};

use crate::physics::{BroadPhaseKind, Fault, Integrator, JointDrives, Pipeline, Shape, StageTimes};
use crate::sim::scenes::CameraHint;

/// Most faults a snapshot carries: the panel lists the newest, and a run that keeps
/// faulting must not copy an ever longer list every step.
pub const MAX_FAULTS_SHOWN: usize = 8;

/// Position of the shape's own origin and its orientation: what a mesh needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyPose {
    /// World position of the shape's origin, m.
    pub position: Vec3,
    /// Shape frame to world.
    pub rotation: Quat,
}

impl BodyPose {
    /// Blends two poses; `t` = 0 gives `self`, 1 gives `other`.
    pub fn lerp(&self, other: &BodyPose, t: f32) -> BodyPose {
        BodyPose {
            position: self.position.lerp(other.position, t),
            rotation: self.rotation.slerp(other.rotation, t),
        }
    }
}

/// One body as the viewer draws and lists it.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyState {
    /// The pose at the newest step.
    pub pose: BodyPose,
    /// The pose one step earlier, to interpolate between steps.
    pub previous: BodyPose,
    /// Index into `ShapeTable::shapes`.
    pub shape_id: u32,
    /// World bounds (min, max) at `pose`.
    pub aabb: (Vec3, Vec3),
    /// Radius of a sphere around the shape origin that holds the body.
    pub bounding_radius: f32,
    /// World position of the centre of mass, m.
    pub center_of_mass: Vec3,
    /// kg; 0 for static bodies.
    pub mass: f32,
    /// False for static bodies and for those taken out of the world (removed or isolated).
    pub is_dynamic: bool,
    /// Moved by a script or a set velocity (drawn in `render::KINEMATIC_COLOR`).
    pub is_kinematic: bool,
    /// Asleep: drawn in the sleep colour.
    pub sleeping: bool,
    /// False for bodies the scene hides (simulated, not drawn, not pickable).
    pub visible: bool,
    /// Spawned a moment ago: the viewer highlights it so the user sees where it appeared.
    pub just_spawned: bool,
    /// Velocity of the centre of mass, m/s.
    pub velocity: Vec3,
    /// rad/s, world axes.
    pub angular_velocity: Vec3,
    /// Bodies it had contact manifolds with in the last step.
    pub touching: u32,
    /// Contact points of those manifolds.
    pub contact_points: u32,
}

/// A joint as the viewer draws it: its two bodies (indices into `Snapshot::bodies`), where it
/// holds each (in the body's axes, from its drawn origin `BodyPose::position`), and the axis
/// it turns or slides about, in body a's axes (hinge, slider, cone-twist).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointSketch {
    /// Body a, body b.
    pub bodies: [usize; 2],
    /// On a, on b.
    pub anchors: [Vec3; 2],
    /// A unit axis, or None.
    pub axis: Option<Vec3>,
    /// Whether each body moves: the arm from a static body's origin to its anchor is not
    /// drawn (a frame's centre is not where it holds a string).
    pub moving: [bool; 2],
}

/// A coloured line in world space, drawn as an overlay (contact normals, debug vectors).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineSegment {
    /// One end, world coordinates, m.
    pub from: Vec3,
    /// The other end, world coordinates, m.
    pub to: Vec3,
    /// Red, green, blue, each in [0, 1].
    pub color: [f32; 3],
}

/// The distinct shapes of the world. `generation` changes whenever the list does, so the
/// renderer rebuilds its meshes only then.
#[derive(Clone, Debug, Default)]
pub struct ShapeTable {
    /// Grows whenever `shapes` changes.
    pub generation: u64,
    /// Each distinct shape once, indexed by `BodyState::shape_id`.
    pub shapes: Arc<Vec<Shape>>,
}

/// The figures the panel shows about the run and its last step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Counters {
    /// The world's simulated time, s: 0 after a reset or scene load, restored with a saved
    /// world.
    pub sim_time: f64,
    /// Steps the world has taken, counted like `sim_time`.
    pub steps: u64,
    /// Steps per wall-clock second, averaged over the last quarter second.
    pub step_rate: f64,
    /// Mean wall time of one `World::step` over the same window, s.
    pub step_wall_time: f64,
    /// Bodies in the world, static, removed and isolated ones included.
    pub bodies: usize,
    /// Dynamic bodies not asleep.
    pub awake: usize,
    /// Candidate pairs from the broad phase in the last step.
    pub pairs: usize,
    /// Contact points of the last step, speculative ones included.
    pub contacts: usize,
    /// Deepest overlap of the last step, m.
    pub max_penetration: f64,
    /// Where the last step's time went.
    pub stages: StageTimes,
    /// Translational and rotational, summed over the dynamic bodies, J.
    pub kinetic_energy: f64,
    /// In the gravity fields, zero at the world origin, summed over the dynamic bodies, J.
    pub potential_energy: f64,
    /// Length of the dynamic bodies' total momentum, kg·m/s.
    pub linear_momentum: f64,
    /// Length of their total angular momentum about the world origin, kg·m²/s.
    pub angular_momentum: f64,
}

/// One point of the plotted history: the [`Counters`] of the same names at `time`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HistorySample {
    /// Simulated time, s.
    pub time: f64,
    /// J
    pub kinetic_energy: f64,
    /// J
    pub potential_energy: f64,
    /// kg·m/s
    pub linear_momentum: f64,
    /// kg·m²/s
    pub angular_momentum: f64,
    /// m
    pub max_penetration: f64,
}

/// One of the scene's materials as its bodies have it now.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialSummary {
    /// A key of the scene's `materials`, `own: BODY` for a body's inline material, or
    /// `spawned` for the bodies spawned from the panel.
    pub name: String,
    /// Restitution of its first body.
    pub restitution: f64,
    /// Friction coefficient of its first body.
    pub friction: f64,
    /// Bodies made of it.
    pub bodies: usize,
}

/// A joint with a motor, servo or spring, as the panel shows it to be changed live.
#[derive(Clone, Debug, PartialEq)]
pub struct DrivenJoint {
    /// Its index in the world's joints (`Command::SetJointDrives`).
    pub joint: u32,
    /// Its kind and its bodies' names, e.g. "hinge chassis – wheel_0".
    pub label: String,
    /// What drives it now.
    pub drives: JointDrives,
}

/// The settings in force, so the UI shows what the simulation really uses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimSettings {
    /// Fixed step, s.
    pub dt: f64,
    /// Simulated seconds per wall-clock second.
    pub time_scale: f64,
    /// The clock is stopped; `StepOnce` still steps.
    pub paused: bool,
    /// The gravity field's acceleration, m/s²: the scene's first (zero if it has none), or
    /// the one last set.
    pub gravity: glam::DVec3,
    /// How orientations are advanced.
    pub integrator: Integrator,
    /// How contacts are handled.
    pub pipeline: Pipeline,
    /// How candidate pairs are found.
    pub broad_phase: BroadPhaseKind,
    /// Substeps (soft pipeline) or slices (classic) per step.
    pub substeps: u32,
    /// Bodies at rest may fall asleep.
    pub sleeping: bool,
    /// Given to spawned bodies: the last value set for every body, or after a scene load
    /// that of its first dynamic body.
    pub restitution: f64,
    /// Given to spawned bodies, like `restitution`.
    pub friction: f64,
}

/// The run at one moment, as the viewer draws and lists it; a new one is published after
/// each batch of steps or commands.
#[derive(Clone, Debug)]
pub struct Snapshot {
    /// The built-in scene name or scene file path the world came from.
    pub scene: String,
    /// Changes on every reset or scene load (the UI re-frames the camera then).
    pub world_generation: u64,
    /// Where the scene's camera starts.
    pub camera: CameraHint,
    /// By body index, as in the world.
    pub bodies: Vec<BodyState>,
    /// By body index: each body's name (as the scene gave it, or the spawn's).
    pub names: Arc<Vec<String>>,
    /// The shapes `bodies` refer to.
    pub shapes: ShapeTable,
    /// Broad-phase boxes (min, max) of the bodies awake in the last step.
    pub broad_phase_boxes: Vec<(Vec3, Vec3)>,
    /// With the uniform grid: the cells those boxes occupy (the report's spatial partition).
    pub broad_phase_cells: Vec<(Vec3, Vec3)>,
    /// Contact points (small crosses) and normals of the last step.
    pub lines: Vec<LineSegment>,
    /// The joints, to be drawn at the bodies' drawn poses.
    pub joints: Vec<JointSketch>,
    /// Figures of the run and its last step.
    pub counters: Counters,
    /// The materials by name, in the order their first body appears.
    pub materials: Vec<MaterialSummary>,
    /// The joints with a motor, servo or spring, in joint order.
    pub driven_joints: Vec<DrivenJoint>,
    /// Oldest first: a sample every 1/30 s of simulated time, the last 600 (20 s).
    pub history: Vec<HistorySample>,
    /// The settings in force.
    pub settings: SimSettings,
    /// Why the last command failed (an unknown scene, an invalid spawn), if it did.
    pub message: Option<String>,
    /// Bodies whose state went non-finite, isolated from the rest of the world (oldest
    /// first, the newest `MAX_FAULTS_SHOWN`).
    pub faults: Vec<Fault>,
    /// How many faults there were in all, listed or not.
    pub fault_count: usize,
    /// Bodies taken out of the world since the scene was loaded because they fell far below
    /// it (see `sim::world_bounds`).
    pub left_world: usize,
    /// When the newest step was taken, so a frame can place itself between `previous` and
    /// `pose` (see `blend_factor`).
    pub published_at: Instant,
    /// The wall time one step stands for at the current time scale, s; 0 when the time
    /// scale is 0.
    pub step_interval: f64,
}

impl Snapshot {
    /// Interpolation factor for a frame drawn at `now`: 0 right after the step, 1 one step
    /// interval later (and when paused, where the newest pose is the one to show).
    pub fn blend_factor(&self, now: Instant) -> f32 {
        if self.settings.paused || self.step_interval <= 0.0 {
            return 1.0;
        }
        let elapsed = now
            .saturating_duration_since(self.published_at)
            .as_secs_f64();
        (elapsed / self.step_interval).clamp(0.0, 1.0) as f32
    }

    /// Each body's pose interpolated at `t` (see `blend_factor`).
    pub fn poses_at(&self, t: f32) -> Vec<BodyPose> {
        self.bodies
            .iter()
            .map(|b| b.previous.lerp(&b.pose, t))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::Simulation;
    use std::time::Duration;

    #[test]
    fn frames_blend_from_the_previous_step_to_the_newest() {
        let mut sim = Simulation::new("falling_box").unwrap();
        sim.step();
        let snapshot = sim.snapshot(Instant::now());
        let published = snapshot.published_at;
        let half = published + Duration::from_secs_f64(snapshot.step_interval / 2.0);
        assert_eq!(snapshot.blend_factor(published), 0.0);
        assert!((snapshot.blend_factor(half) - 0.5).abs() < 1e-3);
        assert_eq!(
            snapshot.blend_factor(published + Duration::from_secs(1)),
            1.0
        );
        let falling = &snapshot.bodies[2];
        let y = snapshot.poses_at(0.5)[2].position.y;
        let midway = (falling.previous.position.y + falling.pose.position.y) / 2.0;
        assert!((y - midway).abs() < 1e-6);
    }
}
