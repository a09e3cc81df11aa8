//! The engine. Nothing here knows about windows, GPUs or user interfaces.
//!
//! The folders follow a step (`World::step`):
//!
//! - [`geometry`]: shapes and what can be asked of one shape (bounds, mass, GJK, EPA, casts);
//! - [`collision`]: the broad phase, the narrow phase and contact manifolds;
//! - [`dynamics`]: bodies, forces, integration, islands and sleep;
//! - [`joints`]: ball, hinge, slider, fixed and distance joints, solved with the contacts;
//! - [`solver`]: the `soft` and `classic` contact solvers;
//! - [`world`]: the step itself and the public entry points, with [`query`] (ray and shape
//!   casts) and [`snapshot`] (save and restore).
//!
//! The items a user needs are re-exported here and in [`crate::prelude`].

pub mod collision;
pub mod dynamics;
pub mod geometry;
pub mod joints;
pub mod query;
pub mod snapshot;
pub mod solver;
pub(crate) mod stage_times;
pub mod world;

pub use collision::broad_phase::{BodyPair, BroadPhase, BroadPhaseKind, Proxy};
pub use collision::contact::{Contact, ContactKind, ContactManifold, FeatureId};
pub use collision::manifold::{contact_manifold, generate_contacts};
pub use dynamics::body::{
    BodyDesc, BodyError, BodyId, MAX_BODY_ENERGY, MAX_FRICTION, Material, Motion, RigidBody,
};
pub use dynamics::containment::{MAX_CONTACT_POSITION, MAX_CONTACT_SPEED};
pub use dynamics::forces::{
    EnvironmentForce, ForceError, MAX_DRAG_COEFFICIENT, MAX_GRAVITY, MAX_WIND_SPEED,
    STANDARD_GRAVITY,
};
pub use dynamics::integrate::Integrator;
pub use dynamics::islands::SleepSettings;
pub use geometry::aabb::Aabb;
pub use geometry::cast::{ShapeHit, cast_support_map, ray_cast_shape};
pub use geometry::compound::{Compound, CompoundPart, MAX_COMPOUND_PARTS};
pub use geometry::epa::{Penetration, SignedDistance, penetration, signed_distance};
pub use geometry::gjk::{GjkResult, PosedShape, SupportMap, gjk_distance, gjk_intersects};
pub use geometry::hull::{
    CONTAINMENT_CHECK_BUDGET, ConvexHull, HullError, HullFace, MAX_HULL_POINTS,
};
pub use geometry::mass::MassProperties;
pub use geometry::shape::{Pose, Shape, ShapeError};
pub use joints::{
    Breaking, Joint, JointDesc, JointDrives, JointError, JointId, JointKind, Motor, Servo, Spring,
};
pub use query::{CastHit, QueryError, ray_cast, shape_cast};
pub use snapshot::{SnapshotError, WorldSnapshot};
pub use solver::classic::{ClassicReport, ClassicSettings, MainLoop};
pub use solver::soft::SoftSolverSettings;
pub use solver::toi::{
    Rewind, TimeOfImpact, bisection_rewind, conservative_advancement, swept_aabb,
};
pub use stage_times::StageTimes;
pub use world::{
    AddBodyError, DEFAULT_MAX_PAIRS, Fault, FaultReason, MAX_BODIES, MAX_STEP, MotionError,
    PairBudgetFault, Pipeline, RemoveError, StepError, World, WorldSettings, WorldTotals,
};
