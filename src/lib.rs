//! rigid: real-time rigid-body physics for convex bodies, after the engine described in
//! "Simulation physique de corps rigides avec interaction", with an interactive viewer.
//!
//! `physics` is the engine; `scene` turns scene files into worlds; `sim` runs a world on its
//! own thread; `render` and `ui` (feature `viewer`) draw it and let a user drive it.

pub mod bench;
pub mod input_file;
pub mod physics;
#[cfg(feature = "viewer")]
pub mod render;
pub mod scene;
pub mod sim;
#[cfg(feature = "viewer")]
pub mod ui;
#[cfg(all(feature = "viewer", target_arch = "wasm32"))]
pub mod web;
