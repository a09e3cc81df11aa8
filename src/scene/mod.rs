//! Scene files: RON descriptions of a world, their validation, and the built-in scenes.
//!
//! The entry points, for the viewer and the headless runner:
//! - [`builtin_scenes`] lists the built-in scenes (`name`, `source`); [`DEFAULT_SCENE`] is the
//!   one to open first; [`find_builtin`] looks one up by name.
//! - [`load_file`] reads and validates a scene file; [`parse`] does the same for text, `origin`
//!   naming it in errors; [`load`] takes a built-in name or a path.
//! - [`Scene::build_world`] makes the `World`. The scene keeps what a world does not: `name`,
//!   `description`, `camera` (eye, target) and `settings.dt`, the step to pass to
//!   `World::step`.
//!
//! Every error is a [`SceneError`] whose message names the file, and where it applies the body
//! (name, or `#index`) and the field: `scenes/foo.ron: body 'crate_3' field
//! 'shape.half_extents.x': must be positive, got -1`. No input makes these functions panic.
//!
//! # Format
//! ```ron
//! Scene(
//!     name: "demo",
//!     description: "A box on a floor.",
//!     settings: (dt: 0.004, integrator: Midpoint),      // or ReportEuler, ExactRotation
//!     camera: (eye: (0, 3, 8), target: (0, 0.5, 0)),
//!     forces: [Gravity(acceleration: (0, -9.81, 0)), LinearDrag(coefficient: 0.01)],
//!     materials: { "wood": (density: 600, restitution: 0.4, friction: 0.6) },
//!     bodies: [
//!         (name: "floor", shape: Cuboid(half_extents: (5, 0.1, 5)), position: (0, -0.1, 0),
//!          static: true),
//!         (name: "box", shape: Cuboid(half_extents: (0.5, 0.5, 0.5)), position: (0, 2, 0),
//!          rotation: Euler(10, 0, 20), material: "wood", angular_velocity: (0, 1, 0)),
//!         (name: "ball", shape: Sphere(radius: 0.2), position: (-2, 0.2, -2), mass: 1.5,
//!          material: (density: 7800, restitution: 0.6, friction: 0.3),
//!          repeat: Grid(count: (5, 1, 5), spacing: (1, 0, 1))),
//!     ],
//! )
//! ```
//! Units are SI and y is up. Shapes: `Sphere(radius)`, `Cuboid(half_extents)`,
//! `Capsule(half_height, radius)` and `Cylinder(half_height, radius)` (both along local y),
//! `Hull(points: [...])`, `Compound(parts: [(shape, position, rotation)])`. Rotations:
//! `Euler(x, y, z)` in degrees about world x, then y, then z, or
//! `AxisAngle(axis: (..), degrees: ..)`. Angular velocities are in rad/s. Generators:
//! `repeat: Grid(count: (nx, ny, nz), spacing: (..), stagger: (..))` and
//! `repeat: Pyramid(layers: n, spacing: (dx, dy))`; copies are named `name_0`, `name_1`, ….
//!
//! A `joints: [...]` list joins bodies named in `bodies` (a generated copy is `name_k`):
//! `(name, body_a, body_b, kind: Ball(anchor) | Hinge(anchor, axis) | Slider(anchor, axis) |
//! ConeTwist(anchor, axis, cone) | Fixed(anchor) | Distance(anchor_a, anchor_b), limits,
//! motor, servo, spring, breaking, colliding)`, or
//! `(name, kind: Chain(links, joint: Ball | Distance, pin))` to join the copies of a generated
//! body in order (see [`JointSpec`]). A body with `kinematic: Velocity(linear, angular)` or
//! `kinematic: Sinusoid(axis, amplitude, angle_axis, angle_amplitude, frequency, phase)` is
//! kinematic and scripted: [`Scene::scripted_motions`] gives the scripts, and [`drive`] applies
//! them before each step (see [`KinematicSpec`]). Joint errors are [`SceneError::Joint`],
//! naming the joint and the field.
//!
//! A scene may make at most [`MAX_BODIES`] bodies; `settings.dt` must lie in [`DT_RANGE`]; a
//! hull takes at most `MAX_HULL_POINTS` points and a compound at most `MAX_COMPOUND_PARTS`
//! parts.

mod build;
mod builtin;
mod error;
mod expand;
mod file;
mod joints;
mod material_ref;
mod parse;
mod rain;
mod script;
mod shapes;
mod validate;

use std::path::Path;

pub use builtin::{BuiltinScene, builtin_scene_names, builtin_scenes, find_builtin};
pub use error::SceneError;
pub use file::{
    BodySpec, Camera, ChainJoint, ForceSpec, JointKindSpec, JointSpec, KinematicSpec, PartSpec,
    Repeat, Rotation, Scene, SceneSettings, ShapeSpec,
};
pub use material_ref::MaterialRef;
pub use parse::parse;
pub use rain::rain_world;
pub use script::{ScriptedMotion, drive};
pub use validate::{DT_RANGE, MAX_BODIES, MAX_FRICTION};

/// The scene a viewer opens when told nothing else.
pub const DEFAULT_SCENE: &str = "falling_box";

/// Reads and validates a scene file; errors name the file as `path` was written.
pub fn load_file(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
    let path = path.as_ref();
    let origin = path.display().to_string();
    let text = crate::input_file::read_text(path).map_err(|error| SceneError::Read {
        file: origin.clone(),
        message: error.to_string(),
    })?;
    parse(&text, &origin)
}

/// A note for the command-line tools when `name` is a built-in scene's and also names a
/// file here: `load` takes the built-in one, and a user who meant the file should hear so.
pub fn shadowed_file_note(name: &str) -> Option<String> {
    (find_builtin(name).is_some() && Path::new(name).exists()).then(|| {
        format!("'{name}' is the built-in scene; the file '{name}' here is not read (name it ./{name} to load it)")
    })
}

/// A built-in scene by name, or else a scene file by path (see `shadowed_file_note`).
pub fn load(name_or_path: &str) -> Result<Scene, SceneError> {
    if let Some(builtin) = find_builtin(name_or_path) {
        return builtin.parse();
    }
    if Path::new(name_or_path).exists() {
        return load_file(name_or_path);
    }
    let names: Vec<&str> = builtin_scene_names().collect();
    Err(SceneError::UnknownScene {
        name: name_or_path.to_owned(),
        available: names.join(", "),
    })
}
