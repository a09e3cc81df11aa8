//! rigid: real-time rigid-body physics for convex bodies, after the engine described in
//! "Simulation physique de corps rigides avec interaction", with an interactive viewer.
//!
//! [`physics`] is the engine; [`scene`] turns scene files into worlds; [`sim`] runs a world
//! on its own thread; `render` and `ui` (feature `viewer`) draw it and let a user drive it.
//! [`prelude`] brings what a program stepping a world needs:
//!
//! ```
//! use rigid::prelude::*;
//!
//! let mut world = World::default();
//! world.forces.push(EnvironmentForce::earth_gravity());
//! let ball = world.add_body(BodyDesc::dynamic(Shape::sphere(0.5)).at(DVec3::Y * 10.0))?;
//! world.step(1.0 / 60.0);
//! assert!(world.body(ball).position.y < 10.0);
//! # Ok::<(), AddBodyError>(())
//! ```

#![warn(missing_docs)]

pub mod cli_arg;
pub mod input_file;
pub mod output_file;
pub mod physics;
#[cfg(not(target_arch = "wasm32"))]
pub mod progress;
#[cfg(feature = "viewer")]
pub mod render;
pub mod scene;
pub mod sim;
#[cfg(feature = "viewer")]
pub mod ui;
#[cfg(all(feature = "viewer", target_arch = "wasm32"))]
pub mod web;

/// What a program that builds and steps a world needs, in one `use rigid::prelude::*`.
pub mod prelude {
    pub use glam::{DMat3, DQuat, DVec3};

    pub use crate::physics::{
        AddBodyError, BodyDesc, BodyId, BroadPhaseKind, CastHit, ClassicSettings, EnvironmentForce,
        Integrator, JointDesc, JointError, JointId, MainLoop, Material, Motion, Pipeline,
        RigidBody, STANDARD_GRAVITY, Shape, SleepSettings, SoftSolverSettings, StepError, World,
        WorldSettings,
    };
}
