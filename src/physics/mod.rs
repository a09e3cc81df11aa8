//! The engine. Nothing here knows about windows, GPUs or user interfaces.
//!
//! Reading order of a step: `forces` → `integrate` (see `World::step`).

pub mod body;
pub mod compound;
pub mod forces;
pub mod hull;
pub mod integrate;
pub mod mass;
pub mod shape;
pub mod world;

pub use body::{BodyDesc, BodyError, BodyId, Material, Motion, RigidBody};
pub use compound::{Compound, CompoundPart};
pub use forces::EnvironmentForce;
pub use hull::{ConvexHull, HullError, HullFace};
pub use integrate::Integrator;
pub use mass::MassProperties;
pub use shape::{Pose, Shape, ShapeError};
pub use world::{World, WorldSettings, WorldTotals};

pub mod aabb;
pub mod broad_phase;
pub mod contact;
pub mod epa;
pub mod gjk;
pub mod manifold;
pub mod query;
pub mod toi;

pub use aabb::Aabb;
pub use broad_phase::{BodyPair, BroadPhase, BroadPhaseKind, Proxy};
pub use contact::{Contact, ContactKind, ContactManifold, FeatureId};
pub use epa::{Penetration, SignedDistance, penetration, signed_distance};
pub use gjk::{GjkResult, PosedShape, SupportMap, gjk_distance, gjk_intersects};
pub use manifold::{contact_manifold, generate_contacts};
pub use query::{CastHit, ray_cast, shape_cast};
pub use toi::{Rewind, TimeOfImpact, bisection_rewind, conservative_advancement, swept_aabb};
