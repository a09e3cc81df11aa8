//! rigid: real-time rigid-body physics for convex bodies, after the engine described in
//! "Simulation physique de corps rigides avec interaction", with an interactive viewer.

pub mod bench;
pub mod physics;
pub mod scene;
