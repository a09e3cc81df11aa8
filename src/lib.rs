//! rigid: real-time rigid-body physics for convex bodies, after the engine described in
//! "Simulation physique de corps rigides avec interaction", with an interactive viewer.

pub mod physics;
#[cfg(feature = "viewer")]
pub mod render;
pub mod sim;
#[cfg(feature = "viewer")]
pub mod ui;
