//! Broad phase (report section 3.1.1): the pairs of bodies whose bounding boxes overlap, the
//! only pairs the narrow phase looks at.
//!
//! Every implementation answers the same question and returns the same sorted pair set:
//! - `BruteForce`: all n(n−1)/2 box tests, the report's method and the reference;
//! - `UniformGrid`: the report's spatial partitioning (section 4.3.2), boxes hashed into cubic cells;
//! - `SweepAndPrune`: boxes kept sorted along one axis between steps; the sort is an insertion
//!   sort, nearly linear when bodies move little, so it is the scalable default.
//!
//! A pair is reported when the boxes overlap (touching counts) and at least one of the two
//! proxies is active. Static bodies are never active, so static-static pairs never appear;
//! a sleeping body is made inactive to skip sleeping-sleeping and sleeping-static pairs.

mod brute_force;
mod sweep_and_prune;
mod uniform_grid;

pub use brute_force::BruteForce;
pub use sweep_and_prune::SweepAndPrune;
pub use uniform_grid::UniformGrid;

use serde::{Deserialize, Serialize};

use crate::physics::aabb::Aabb;
use crate::physics::body::{BodyId, RigidBody};

/// What the broad phase knows about one body; proxies are indexed like the world's bodies.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Proxy {
    pub aabb: Aabb,
    /// A dynamic, awake body. Pairs of two inactive proxies are skipped.
    pub active: bool,
}

impl Proxy {
    /// The body's tight box grown by `margin`, active when the body is dynamic.
    pub fn of_body(body: &RigidBody, margin: f64) -> Proxy {
        Proxy {
            aabb: Aabb::of_body(body).fattened(margin),
            active: body.is_dynamic(),
        }
    }
}

/// Two bodies, lower id first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BodyPair {
    pub a: BodyId,
    pub b: BodyId,
}

impl BodyPair {
    /// Orders the two indices so that a pair has a single spelling.
    pub fn new(i: usize, j: usize) -> BodyPair {
        let (low, high) = if i < j { (i, j) } else { (j, i) };
        BodyPair {
            a: BodyId(low as u32),
            b: BodyId(high as u32),
        }
    }
}

/// The pair rule every implementation applies.
pub fn wants_pair(p: &Proxy, q: &Proxy) -> bool {
    (p.active || q.active) && p.aabb.overlaps(&q.aabb)
}

pub trait BroadPhase {
    /// Takes this step's proxies (index = body index) and returns the overlapping pairs,
    /// sorted and without duplicates. Implementations may keep state between calls.
    fn find_pairs(&mut self, proxies: &[Proxy]) -> Vec<BodyPair>;
}

/// The implementations, selectable in settings.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum BroadPhaseKind {
    BruteForce,
    /// Cubic cells of `cell_size` metres; best near the size of a typical body.
    UniformGrid {
        cell_size: f64,
    },
    /// The default: scales and updates incrementally.
    #[default]
    SweepAndPrune,
}

impl BroadPhaseKind {
    pub fn create(self) -> Box<dyn BroadPhase + Send> {
        match self {
            BroadPhaseKind::BruteForce => Box::new(BruteForce),
            BroadPhaseKind::UniformGrid { cell_size } => Box::new(UniformGrid::new(cell_size)),
            BroadPhaseKind::SweepAndPrune => Box::new(SweepAndPrune::default()),
        }
    }
}
