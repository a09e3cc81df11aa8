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
//!
//! The world runs the chosen implementation over the awake bodies only, and finds their
//! pairs with idle bodies in an `AabbTree` of the idle boxes (`SplitBroadPhase`).

mod aabb_tree;
mod brute_force;
mod sweep_and_prune;
mod uniform_grid;

pub use aabb_tree::AabbTree;
pub use brute_force::BruteForce;
pub use sweep_and_prune::SweepAndPrune;
pub use uniform_grid::{MAX_CELLS_PER_PROXY, UniformGrid};

use serde::{Deserialize, Serialize};

use crate::physics::dynamics::body::{BodyId, RigidBody};
use crate::physics::geometry::aabb::Aabb;

/// What the broad phase knows about one body; proxies are indexed like the world's bodies.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Proxy {
    /// The body's world box, grown by the margin the proxy was made with.
    pub aabb: Aabb,
    /// A dynamic, awake body. Pairs of two inactive proxies are skipped.
    pub active: bool,
}

impl Proxy {
    /// The body's tight box grown by `margin`, active when the body is dynamic.
    pub fn of_body(body: &RigidBody, margin: f64) -> Proxy {
        Proxy {
            aabb: Aabb::of_body(body).fattened(margin),
            active: body.motion.moves(),
        }
    }
}

/// Two bodies, lower id first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BodyPair {
    /// The body with the lower id.
    pub a: BodyId,
    /// The body with the higher id.
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

/// Sorts pairs into their `Ord` order (by a, then b) through one 64-bit key: the derived
/// comparison of two fields costs a branch more per step of the sort, and the broad phase
/// sorts thousands of pairs every step.
pub fn sort_pairs(pairs: &mut [BodyPair]) {
    pairs.sort_unstable_by_key(|p| (u64::from(p.a.0) << 32) | u64::from(p.b.0));
}

/// The pair rule every implementation applies.
pub fn wants_pair(p: &Proxy, q: &Proxy) -> bool {
    (p.active || q.active) && p.aabb.overlaps(&q.aabb)
}

/// A broad-phase algorithm: from one step's proxies, the pairs whose boxes overlap.
pub trait BroadPhase {
    /// Takes this step's proxies (index = body index) and replaces the contents of `pairs`
    /// with the overlapping pairs, sorted and without duplicates. The caller keeps `pairs`
    /// between steps, so a step reuses its memory. Implementations may keep state between
    /// calls.
    fn fill_pairs(&mut self, proxies: &[Proxy], pairs: &mut Vec<BodyPair>) {
        self.fill_pairs_within(proxies, pairs, usize::MAX);
    }

    /// `fill_pairs`, keeping at most `limit` pairs: the search stops once that many are
    /// found, so a pile of bodies at one point costs `limit` pairs of memory rather than
    /// n²/2. Returns whether pairs were left out; which ones is fixed for given proxies.
    fn fill_pairs_within(
        &mut self,
        proxies: &[Proxy],
        pairs: &mut Vec<BodyPair>,
        limit: usize,
    ) -> bool;

    /// `fill_pairs` into a new list.
    fn find_pairs(&mut self, proxies: &[Proxy]) -> Vec<BodyPair> {
        let mut pairs = Vec::new();
        self.fill_pairs(proxies, &mut pairs);
        pairs
    }
}

/// The implementations, selectable in settings.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum BroadPhaseKind {
    /// Every pair tested: O(n²), the reference the others must agree with.
    BruteForce,
    /// Cubic cells of `cell_size` metres; best near the size of a typical body.
    UniformGrid {
        /// Edge length of a cell, m; a value that is not positive and finite means 1 m.
        cell_size: f64,
    },
    /// The default: scales and updates incrementally.
    #[default]
    SweepAndPrune,
}

impl BroadPhaseKind {
    /// A new instance of this implementation, holding no state yet.
    pub fn create(self) -> Box<dyn BroadPhase + Send> {
        match self {
            BroadPhaseKind::BruteForce => Box::new(BruteForce),
            BroadPhaseKind::UniformGrid { cell_size } => Box::new(UniformGrid::new(cell_size)),
            BroadPhaseKind::SweepAndPrune => Box::new(SweepAndPrune::default()),
        }
    }
}

/// The world's broad phase: the chosen implementation over the awake bodies' proxies, plus
/// an `AabbTree` of the idle (static and sleeping) bodies' boxes that each awake box queries.
/// The tree is rebuilt only when the set of idle bodies changed, so on other steps idle
/// bodies cost nothing. The pairs are the same set `wants_pair` gives over all proxies.
pub struct SplitBroadPhase {
    kind: BroadPhaseKind,
    awake_phase: Box<dyn BroadPhase + Send>,
    idle: AabbTree,
    /// False until the tree is first built (a new or cloned broad phase).
    built: bool,
    /// The awake bodies' proxies, compacted for `awake_phase`, the pairs it finds among
    /// them and the awake bodies' pairs with idle ones (all reused between steps).
    awake_proxies: Vec<Proxy>,
    awake_pairs: Vec<BodyPair>,
    idle_pairs: Vec<BodyPair>,
}

impl SplitBroadPhase {
    /// A split broad phase that runs `kind` over the awake bodies; its tree of idle bodies
    /// is built on the first `fill_pairs`.
    pub fn new(kind: BroadPhaseKind) -> Self {
        SplitBroadPhase {
            kind,
            awake_phase: kind.create(),
            idle: AabbTree::default(),
            built: false,
            awake_proxies: Vec::new(),
            awake_pairs: Vec::new(),
            idle_pairs: Vec::new(),
        }
    }

    /// The implementation run over the awake bodies.
    pub fn kind(&self) -> BroadPhaseKind {
        self.kind
    }

    /// Replaces the contents of `pairs` with the pairs among `proxies` (indexed by body)
    /// where `awake` lists the active ones, sorted. `idle_changed` must be true whenever an
    /// inactive proxy changed since the last call.
    pub fn fill_pairs(
        &mut self,
        proxies: &[Proxy],
        awake: &[u32],
        idle_changed: bool,
        pairs: &mut Vec<BodyPair>,
    ) {
        self.fill_pairs_within(proxies, awake, idle_changed, pairs, usize::MAX);
    }

    /// `fill_pairs`, keeping at most `limit` pairs (see `BroadPhase::fill_pairs_within`);
    /// returns whether pairs were left out.
    pub fn fill_pairs_within(
        &mut self,
        proxies: &[Proxy],
        awake: &[u32],
        idle_changed: bool,
        pairs: &mut Vec<BodyPair>,
        limit: usize,
    ) -> bool {
        if idle_changed || !self.built {
            self.built = true;
            let idle = proxies.iter().enumerate().filter(|(_, p)| !p.active);
            let boxes = idle.filter(|(_, p)| p.aabb.min.cmple(p.aabb.max).all());
            self.idle.rebuild(boxes.map(|(i, p)| (p.aabb, i as u32)));
        }
        self.awake_proxies.clear();
        self.awake_proxies
            .extend(awake.iter().map(|&i| proxies[i as usize]));
        // The awake phase's pairs come sorted, and `awake` ascends, so renaming them keeps
        // them sorted: only the pairs with an idle body need sorting, then the two merge.
        let mut truncated =
            (self.awake_phase).fill_pairs_within(&self.awake_proxies, &mut self.awake_pairs, limit);
        for pair in &mut self.awake_pairs {
            *pair = BodyPair::new(
                awake[pair.a.index()] as usize,
                awake[pair.b.index()] as usize,
            );
        }
        debug_assert!(self.awake_pairs.is_sorted());
        let idle_pairs = &mut self.idle_pairs;
        idle_pairs.clear();
        // Room for the idle pairs is what the awake ones left: the merged list stays
        // within `limit`.
        let room = limit.saturating_sub(self.awake_pairs.len());
        for &i in awake {
            let aabb = &proxies[i as usize].aabb;
            self.idle.query(aabb, |j| {
                if idle_pairs.len() < room {
                    idle_pairs.push(BodyPair::new(i as usize, j as usize));
                } else {
                    truncated = true;
                }
            });
            if truncated && idle_pairs.len() >= room {
                break;
            }
        }
        sort_pairs(idle_pairs);
        merge_sorted(&self.awake_pairs, idle_pairs, pairs);
        truncated
    }
}

/// Replaces the contents of `merged` with the elements of two sorted lists, sorted.
fn merge_sorted<T: Copy + Ord>(x: &[T], y: &[T], merged: &mut Vec<T>) {
    merged.clear();
    merged.reserve(x.len() + y.len());
    let (mut i, mut j) = (0, 0);
    while i < x.len() && j < y.len() {
        if y[j] < x[i] {
            merged.push(y[j]);
            j += 1;
        } else {
            merged.push(x[i]);
            i += 1;
        }
    }
    merged.extend_from_slice(&x[i..]);
    merged.extend_from_slice(&y[j..]);
}

impl Clone for SplitBroadPhase {
    /// Its state is only a cache: a clone starts fresh (the world rebuilds the tree).
    fn clone(&self) -> Self {
        SplitBroadPhase::new(self.kind)
    }
}

impl std::fmt::Debug for SplitBroadPhase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "SplitBroadPhase({:?}, {} idle)",
            self.kind,
            self.idle.len()
        )
    }
}
