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
use crate::physics::solver::solver_bodies::{KINEMATIC_SCALE, SharedBodies, SolverBody};

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

/// Readies `scratch` for the push-out of `points` (marked by `mark_deep`) over this step's
/// substeps, with `bodies` the solver's slots.
pub(super) fn prepare(
    scratch: &mut PushOutScratch,
    bodies: &[SolverBody],
    points: &[PointConstraint],
) {
    let slot_held = |slot: u32| held(&bodies[slot as usize]);
    scratch.impulses.resize(points.len(), 0.0);
    scratch.points.clear();
    scratch.points.extend(points.iter().map(|c| PushPoint {
        slots: c.slots,
        deep: c.deep,
    }));
    scratch.on_held.clear();
    let on_held = points
        .iter()
        .enumerate()
        .filter(|(_, c)| c.slots.into_iter().any(slot_held));
    scratch.on_held.extend(on_held.map(|(k, _)| k as u32));
    scratch.reach.clear();
    let reach = |body| {
        if held(body) {
            Reach::Held
        } else {
            Reach::Still
        }
    };
    scratch.reach.extend(bodies.iter().map(reach));
}

/// What the push-out keeps between steps, so that it allocates nothing once grown: the
/// points' accumulated push-out impulses, and which bodies the push-out has reached.
#[derive(Clone, Debug, Default)]
pub(super) struct PushOutScratch {
    /// One per point: its accumulated push-out impulse in this substep, N·s.
    impulses: Vec<f64>,
    /// One per point: its slots, and whether it is deep, read without its whole record.
    points: Vec<PushPoint>,
    /// The points that touch a fixed or kinematic body (`held`).
    on_held: Vec<u32>,
    /// One per slot: what the push-out may do to it (`Reach`).
    reach: Vec<Reach>,
}

/// A point as the push-out's sweeps first read it.
#[derive(Clone, Copy, Debug)]
struct PushPoint {
    slots: [u32; 2],
    deep: bool,
}

/// Where the push-out stands with a body in this substep.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Reach {
    /// Not pushed so far: a point between two such bodies that is not deep adds nothing.
    Still,
    /// Pushed (or pushing back) by some point.
    Moving,
    /// Fixed or kinematic: never moved by the push-out.
    Held,
}

/// Solves the push-out of `points` for a substep of length `h` (`scratch` from
/// `prepare`, in the same step).
///
/// A point that is not deep and whose bodies the push-out has not reached adds nothing
/// (its target never pushes, and neither body moves), so the sweeps skip it without its
/// record: the work follows the deep points and the bodies they push, not the scene.
pub(super) fn solve(
    bodies: &mut [SolverBody],
    points: &[PointConstraint],
    max_push_out: f64,
    scratch: &mut PushOutScratch,
    h: f64,
) {
    let PushOutScratch {
        impulses,
        points: push_points,
        on_held,
        reach,
    } = scratch;
    impulses.fill(0.0);
    for r in reach.iter_mut().filter(|r| **r == Reach::Moving) {
        *r = Reach::Still;
    }
    let target = |c: &PointConstraint| {
        if c.deep && c.separation < 0.0 {
            max_push_out
        } else {
            // Open: it may close its gap in this substep; touching: not move further in.
            c.separation.max(0.0) / -h
        }
    };
    // SAFETY: used on this thread only.
    let shared = unsafe { SharedBodies::new(bodies) };
    let mut sweep = |k: usize, impulse: &mut f64| {
        let PushPoint { slots, deep } = push_points[k];
        let reached = slots.map(|slot| reach[slot as usize] == Reach::Moving);
        if !deep && reached == [false, false] {
            return;
        }
        let c = &points[k];
        if push_apart(&shared, c, target(c), impulse) {
            for slot in slots {
                if reach[slot as usize] == Reach::Still {
                    reach[slot as usize] = Reach::Moving;
                }
            }
        }
    };
    for _ in 0..ITERATIONS {
        for (k, impulse) in impulses.iter_mut().enumerate() {
            sweep(k, impulse);
        }
    }
    // The sweeps leave a crowd's lowest bodies still pushed down by those above: a fixed or
    // kinematic body's points have the last word, so that nothing is pushed through it.
    for &k in on_held.iter() {
        sweep(k as usize, &mut 0.0);
    }
}

/// Whether the push-out never moves `body`: fixed, or kinematic.
fn held(body: &SolverBody) -> bool {
    body.inv_mass == 0.0 || body.inv_mass == 1.0 / KINEMATIC_SCALE
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
