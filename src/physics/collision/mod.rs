//! Which bodies touch and where: the broad phase over the bodies' boxes, the narrow phase
//! over its pairs, contact manifolds by shape pair, and what the contacts remember between
//! steps (carried manifolds, warm-start impulses).

pub mod broad_phase;
pub(crate) mod closing_speed;
pub mod contact;
pub(crate) mod contact_cache;
pub mod manifold;
pub(crate) mod manifold_memory;
pub(crate) mod narrow_phase;
pub(crate) mod separating_axis;
pub(crate) mod sorted_seek;
