//! Shapes and what can be asked of them alone: bounds, mass properties, support points,
//! distances (GJK), penetration depths (EPA) and casts. Nothing here knows a body.

pub mod aabb;
pub mod cast;
pub mod compound;
pub mod epa;
pub mod gjk;
pub mod hull;
pub mod mass;
pub(crate) mod nearest_surface;
pub(crate) mod segment;
pub mod shape;
