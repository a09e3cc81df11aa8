//! **Push-out** of deep overlaps (see `solve::Pass::Biased`). A point is deep when it
//! begins the step deeper than `deep_overlap` beyond what its load explains (`mark_deep`).
//! In a step with deep points, after each substep's biased pass, the bodies' push-out
//! momenta (`SolverBody::push_out`) are solved as a velocity of their own: a deep point
//! moves its bodies apart at `max_push_out`, and no other point lets its bodies move
//! further into each other, so that a crowd created on a floor does not push its lowest
//! bodies through it. **Integrate positions** then moves each body by its push-out, at most
//! `max_push_out` fast, and its velocity never keeps any of it. Only the linear motion is
//! pushed: a push-out must not spin bodies up.

use super::constraint::PointConstraint;
use super::solve::Softness;
use crate::physics::dynamics::body::RigidBody;
use crate::physics::solver::solver_bodies::{SharedBodies, SolverBody};

/// Sweeps over the points per substep.
const ITERATIONS: usize = 4;

/// Marks the deep points among `points` (prepared, with the impulses they ended the last
/// step with): deeper than `deep_overlap` beyond the spring's static deflection under the
/// load their pair carries, the sum of those impulses (a rocking pair's points come and
/// go, and a new one starts with none). Returns whether there is any.
pub(super) fn mark_deep(
    points: &mut [PointConstraint],
    softness: Softness,
    deep_overlap: f64,
) -> bool {
    let mut any = false;
    for pair in points.chunk_by_mut(|a, b| a.same_bodies(b)) {
        let load: f64 = pair.iter().map(|c| c.impulse.normal).sum();
        for c in pair {
            let load_depth = softness.depth_under_load(load, c.normal_mass);
            c.deep = c.separation + load_depth < -deep_overlap;
            any |= c.deep;
        }
    }
    any
}

/// What the push-out keeps between steps, so that it allocates nothing once grown.
///
/// A point that is not deep and whose bodies the push-out has not reached in this substep
/// adds nothing (its target never pushes, and neither body moves): the sweeps visit only
/// the deep points and, once a body is reached, that body's points. So the work follows the
/// deep points and the bodies they push, not the scene.
#[derive(Clone, Debug, Default)]
pub(super) struct PushOutScratch {
    /// The deep points.
    deep: Vec<u32>,
    /// The points that touch a fixed or kinematic body.
    on_held: Vec<u32>,
    /// The points of the body in slot s are `body_points[point_starts[s]..point_starts[s +
    /// 1]]` (none for a held body).
    point_starts: Vec<u32>,
    body_points: Vec<u32>,
    /// One per slot: what the push-out may do to it.
    reach: Vec<Reach>,
    /// The slots reached in this substep.
    reached: Vec<u32>,
    /// One bit per point: the points the sweeps visit in this substep.
    visited: Vec<u64>,
    /// One per point: its accumulated push-out impulse in this substep, N·s (set when the
    /// point is first visited).
    impulses: Vec<f64>,
}

/// Where the push-out stands with a body in this substep.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Reach {
    /// Not pushed so far.
    Still,
    /// Pushed (or pushing back) by some point.
    Moving,
    /// Fixed or kinematic: never moved by the push-out.
    Held,
}

/// Readies `scratch` for the push-out of `points` (marked by `mark_deep`) over this step's
/// substeps, with `slot_count` solver slots: the fixed slot, then those of the `awake`
/// bodies in order (then padding, which no point holds).
pub(super) fn prepare(
    scratch: &mut PushOutScratch,
    (bodies, awake): (&[RigidBody], &[u32]),
    slot_count: usize,
    points: &[PointConstraint],
) {
    let kinematic = |k: &u32| bodies[*k as usize].is_kinematic();
    let reach = |held| if held { Reach::Held } else { Reach::Still };
    scratch.reach.clear();
    scratch.reach.push(Reach::Held);
    scratch.reach.extend(awake.iter().map(kinematic).map(reach));
    scratch.reach.resize(slot_count, Reach::Still);
    // Reached in the last step: by slots this step may hand to other bodies, or not have.
    scratch.reached.clear();
    let reach = &scratch.reach;
    let on_held = |c: &PointConstraint| c.slots.iter().any(|&s| reach[s as usize] == Reach::Held);
    scratch.deep.clear();
    scratch.deep.extend(indices_where(points, |c| c.deep));
    scratch.on_held.clear();
    scratch.on_held.extend(indices_where(points, on_held));
    group_by_body(scratch, points);
    scratch.visited.resize(points.len().div_ceil(64), 0);
    scratch.impulses.resize(points.len(), 0.0);
}

/// The indices of the `points` that `keep` keeps.
fn indices_where<'a>(
    points: &'a [PointConstraint],
    keep: impl Fn(&PointConstraint) -> bool + 'a,
) -> impl Iterator<Item = u32> + 'a {
    (points.iter().enumerate())
        .filter(move |(_, c)| keep(c))
        .map(|(k, _)| k as u32)
}

/// Fills `point_starts` and `body_points` from the `points`' slots (a counting sort by
/// slot).
fn group_by_body(scratch: &mut PushOutScratch, points: &[PointConstraint]) {
    let PushOutScratch {
        point_starts,
        body_points,
        reach,
        ..
    } = scratch;
    let moving_slots = |c: &PointConstraint| {
        let [a, b] = c.slots;
        let b = (b != a).then_some(b);
        [Some(a), b]
            .into_iter()
            .flatten()
            .filter(|&s| reach[s as usize] != Reach::Held)
    };
    // Each slot's count at its place, summed into where its points end; filled from the
    // last point back, each slot's place counts down to where its points start.
    point_starts.clear();
    point_starts.resize(reach.len() + 1, 0);
    for s in points.iter().flat_map(moving_slots) {
        point_starts[s as usize] += 1;
    }
    for s in 1..point_starts.len() {
        point_starts[s] += point_starts[s - 1];
    }
    body_points.clear();
    body_points.resize(point_starts[reach.len()] as usize, 0);
    for (k, c) in points.iter().enumerate().rev() {
        for s in moving_slots(c) {
            point_starts[s as usize] -= 1;
            body_points[point_starts[s as usize] as usize] = k as u32;
        }
    }
}

/// Solves the push-out of `points` for a substep of length `h` (`scratch` from
/// `prepare`, in the same step).
pub(super) fn solve(
    bodies: &mut [SolverBody],
    points: &[PointConstraint],
    max_push_out: f64,
    scratch: &mut PushOutScratch,
    h: f64,
) {
    for &s in &scratch.reached {
        scratch.reach[s as usize] = Reach::Still;
    }
    scratch.reached.clear();
    scratch.visited.fill(0);
    for k in 0..scratch.deep.len() {
        scratch.visit(scratch.deep[k]);
    }
    // SAFETY: used on this thread only.
    let shared = unsafe { SharedBodies::new(bodies) };
    let sweep = Sweep {
        bodies: &shared,
        points,
        max_push_out,
        h,
    };
    for _ in 0..ITERATIONS {
        for word in 0..scratch.visited.len() {
            // Read again after each point: a point may add later points of this word.
            let mut after = 0;
            while let Some(bit) = next_bit(scratch.visited[word], after) {
                let k = word * 64 + bit;
                scratch.impulses[k] = sweep.push(scratch, k, scratch.impulses[k]);
                after = bit + 1;
            }
        }
    }
    // The sweeps leave a crowd's lowest bodies still pushed down by those above: a fixed or
    // kinematic body's points have the last word, so that nothing is pushed through it.
    for i in 0..scratch.on_held.len() {
        let k = scratch.on_held[i] as usize;
        if scratch.is_visited(k) {
            sweep.push(scratch, k, 0.0);
        }
    }
}

/// The lowest set bit of `word` at `from` or above.
fn next_bit(word: u64, from: usize) -> Option<usize> {
    let above = if from < 64 {
        word & (u64::MAX << from)
    } else {
        0
    };
    (above != 0).then(|| above.trailing_zeros() as usize)
}

impl PushOutScratch {
    /// Whether point `k` is visited in this substep.
    fn is_visited(&self, k: usize) -> bool {
        self.visited[k / 64] & (1 << (k % 64)) != 0
    }

    /// Marks point `k` to be visited from now on in this substep.
    fn visit(&mut self, k: u32) {
        if !self.is_visited(k as usize) {
            self.visited[k as usize / 64] |= 1 << (k % 64);
            self.impulses[k as usize] = 0.0;
        }
    }

    /// Marks the body in `slot` reached, and its points to be visited.
    fn reach(&mut self, slot: u32) {
        if self.reach[slot as usize] != Reach::Still {
            return;
        }
        self.reach[slot as usize] = Reach::Moving;
        self.reached.push(slot);
        let range = self.point_starts[slot as usize]..self.point_starts[slot as usize + 1];
        for i in range {
            self.visit(self.body_points[i as usize]);
        }
    }
}

/// What a push-out sweep reads.
struct Sweep<'a> {
    bodies: &'a SharedBodies<'a>,
    points: &'a [PointConstraint],
    max_push_out: f64,
    h: f64,
}

impl Sweep<'_> {
    /// Solves point `k`, whose accumulated push-out impulse is `accumulated`, marks its
    /// bodies reached when it pushes them, and returns the new accumulated impulse.
    fn push(&self, scratch: &mut PushOutScratch, k: usize, accumulated: f64) -> f64 {
        let c = &self.points[k];
        let target = if c.deep && c.separation < 0.0 {
            self.max_push_out
        } else {
            // Open: it may close its gap in this substep; touching: not move further in.
            c.separation.max(0.0) / -self.h
        };
        let mut impulse = accumulated;
        if push_apart(self.bodies, c, target, &mut impulse) {
            let [a, b] = c.slots;
            scratch.reach(a);
            scratch.reach(b);
        }
        impulse
    }
}

/// Adds the least impulse along `c`'s normal (keeping the accumulated `impulse` a push)
/// that has its bodies' push-out part at `speed` (negative: closing) or faster. Returns
/// whether it added any.
fn push_apart(bodies: &SharedBodies, c: &PointConstraint, speed: f64, impulse: &mut f64) -> bool {
    let [slot_a, slot_b] = c.slots;
    let (a, b) = (bodies.get(slot_a), bodies.get(slot_b));
    let mass = a.inv_mass + b.inv_mass;
    if mass == 0.0 {
        return false;
    }
    let normal = c.normal();
    let apart = normal.dot(b.push_out_velocity() - a.push_out_velocity());
    let accumulated = (*impulse + (speed - apart) / mass).max(0.0);
    let applied = accumulated - *impulse;
    *impulse = accumulated;
    bodies.add_push_out(slot_a, -normal * applied);
    bodies.add_push_out(slot_b, normal * applied);
    applied != 0.0
}
