//! The worlds the viewer can show: the built-in scenes of `scene`, or a scene file by path.

use glam::Vec3;

use crate::physics::World;
use crate::scene::{self, ScriptedMotion};
use crate::sim::snapshot::BodyPose;

pub use crate::scene::DEFAULT_SCENE;

/// Where the camera starts: it looks from `eye` at `target`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraHint {
    /// Camera position, m.
    pub eye: Vec3,
    /// The point it looks at, m.
    pub target: Vec3,
    /// The body the camera moves with, if any (a scene's `camera.follow`).
    pub follow: Option<FollowedBody>,
}

/// A body the camera moves with, and where it was when the camera was placed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FollowedBody {
    /// Its index in the world's body list.
    pub index: usize,
    /// Its position when the scene starts, m.
    pub start: Vec3,
}

impl CameraHint {
    /// How far the followed body is from where it started, at `poses`: what the camera
    /// moves by. Zero when the hint follows no body, or one past the end of `poses`.
    pub fn follow_shift(&self, poses: &[BodyPose]) -> Vec3 {
        let followed = self
            .follow
            .and_then(|f| Some((poses.get(f.index)?, f.start)));
        followed.map_or(Vec3::ZERO, |(pose, start)| pose.position - start)
    }
}

/// A world ready to run, with the camera that frames it.
#[derive(Clone, Debug)]
pub struct SceneSetup {
    /// The world to run: built from a scene, or restored from a saved world.
    pub world: World,
    /// Where the camera starts.
    pub camera: CameraHint,
    /// Per body index: simulated but not drawn.
    pub hidden: Vec<bool>,
    /// Per body index: the scene's name for its material (the panel edits them by name).
    pub materials: Vec<String>,
    /// The scripts of the scene's kinematic bodies, driven before each step.
    pub motions: Vec<ScriptedMotion>,
}

/// The names of the built-in scenes, in the order the viewer lists them.
pub fn scene_names() -> impl Iterator<Item = &'static str> {
    scene::builtin_scene_names()
}

/// Builds a built-in scene by name, or a scene file by path; errors name the file, body and
/// field.
pub fn build(name_or_path: &str) -> Result<SceneSetup, String> {
    let loaded = scene::load(name_or_path).map_err(|e| e.to_string())?;
    let world = loaded.build_world().map_err(|e| e.to_string())?;
    let follow = loaded.followed_body().map_err(|e| e.to_string())?;
    let follow = follow.map(|index| FollowedBody {
        index,
        start: world.bodies()[index].position.as_vec3(),
    });
    Ok(SceneSetup {
        motions: loaded.scripted_motions().map_err(|e| e.to_string())?,
        hidden: loaded.hidden_bodies(),
        materials: loaded.material_names(),
        world,
        camera: CameraHint {
            eye: loaded.camera.eye.as_vec3(),
            target: loaded.camera.target.as_vec3(),
            follow,
        },
    })
}
