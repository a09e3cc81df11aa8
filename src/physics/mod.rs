//! The engine. Nothing here knows about windows, GPUs or user interfaces.
//!
//! Reading order of a step (see `World::step`): broad phase → narrow phase → islands/sleep →
//! solve (forces, integration and contacts, in substeps) → diagnostics.

pub mod aabb;
pub mod awake_set;
pub mod body;
pub mod broad_phase;
pub mod classic;
pub mod closing_speed;
pub mod compound;
pub mod contact;
pub mod contact_cache;
pub mod contact_colors;
pub mod epa;
pub mod forces;
pub mod gjk;
pub mod hull;
pub mod impulse;
pub mod integrate;
pub mod islands;
pub mod lanes;
pub mod manifold;
pub mod manifold_memory;
pub mod mass;
pub mod narrow_phase;
pub mod nearest_surface;
pub mod query;
pub mod segment;
pub mod shape;
pub mod snapshot;
pub mod soft_solver;
pub mod solver_bodies;
pub mod sorted_seek;
pub mod stage_times;
pub mod toi;
pub mod union_find;
pub mod world;

pub use aabb::Aabb;
pub use body::{BodyDesc, BodyError, BodyId, Material, Motion, RigidBody};
pub use broad_phase::{BodyPair, BroadPhase, BroadPhaseKind, Proxy};
pub use compound::{Compound, CompoundPart};
pub use contact::{Contact, ContactKind, ContactManifold, FeatureId};
pub use epa::{Penetration, SignedDistance, penetration, signed_distance};
pub use forces::EnvironmentForce;
pub use gjk::{GjkResult, PosedShape, SupportMap, gjk_distance, gjk_intersects};
pub use hull::{ConvexHull, HullError, HullFace, MAX_HULL_POINTS};
pub use integrate::Integrator;
pub use manifold::{contact_manifold, generate_contacts};
pub use mass::MassProperties;
pub use query::{CastHit, ray_cast, shape_cast};
pub use shape::{Pose, Shape, ShapeError};
pub use snapshot::{SnapshotError, WorldSnapshot};
pub use stage_times::StageTimes;
pub use toi::{Rewind, TimeOfImpact, bisection_rewind, conservative_advancement, swept_aabb};
pub use world::{
    AddBodyError, Fault, MAX_BODIES, MAX_STEP, Pipeline, RemoveError, StepError, World,
    WorldSettings, WorldTotals,
};
