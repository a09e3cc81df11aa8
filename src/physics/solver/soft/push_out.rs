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

/// Solves the push-out of `points` for a substep of length `h`, with `impulses` (one per
/// point) as the accumulated push-out impulses.
pub(super) fn solve(
    bodies: &mut [SolverBody],
    points: &[PointConstraint],
    max_push_out: f64,
    impulses: &mut Vec<f64>,
    h: f64,
) {
    impulses.clear();
    impulses.resize(points.len(), 0.0);
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
    for _ in 0..ITERATIONS {
        for (c, impulse) in points.iter().zip(impulses.iter_mut()) {
            push_apart(&shared, c, target(c), impulse);
        }
    }
    // The sweeps leave a crowd's lowest bodies still pushed down by those above: a fixed or
    // kinematic body's points have the last word, so that nothing is pushed through it.
    for c in points.iter().filter(|c| touches_a_held_body(&shared, c)) {
        push_apart(&shared, c, target(c), &mut 0.0);
    }
}

/// Whether one of `c`'s bodies is one the push-out never moves: fixed, or kinematic.
fn touches_a_held_body(bodies: &SharedBodies, c: &PointConstraint) -> bool {
    let held = |slot| {
        let inv_mass = bodies.get(slot).inv_mass;
        inv_mass == 0.0 || inv_mass == 1.0 / KINEMATIC_SCALE
    };
    c.slots.into_iter().any(held)
}

/// Adds the least impulse along `c`'s normal (keeping the accumulated `impulse` a push)
/// that has its bodies' push-out part at `speed` (negative: closing) or faster.
fn push_apart(bodies: &SharedBodies, c: &PointConstraint, speed: f64, impulse: &mut f64) {
    let [slot_a, slot_b] = c.slots;
    let (a, b) = (bodies.get(slot_a), bodies.get(slot_b));
    let mass = a.inv_mass + b.inv_mass;
    if mass == 0.0 {
        return;
    }
    let normal = c.normal();
    let apart = normal.dot(b.push_out_velocity() - a.push_out_velocity());
    let accumulated = (*impulse + (speed - apart) / mass).max(0.0);
    let applied = accumulated - *impulse;
    *impulse = accumulated;
    bodies.add_push_out(slot_a, -normal * applied);
    bodies.add_push_out(slot_b, normal * applied);
}
