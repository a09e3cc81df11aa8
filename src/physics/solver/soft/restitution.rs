//! **Restitution**, once per step after the substeps: contacts that were approaching faster
//! than the threshold leave at ε times their approach speed.

use super::constraint::{PointConstraint, PointImpact};
use crate::physics::solver::contact_colors::ContactColors;
use crate::physics::solver::lanes::Portable;
use crate::physics::solver::solver_bodies::{SharedBodies, SolverBodies};

/// One pass, in contact order rather than colour order, on one thread. A body bouncing off
/// two things in one step gets both rebounds one after the other, and the second changes the
/// first's outgoing speed: the order decides how much energy that adds, and in contact order
/// a bouncing body never gains (BENCHMARKS.md, "Restitution order"). A single pass is cheap to
/// keep serial.
pub(super) fn apply_restitution(
    slots: &mut SolverBodies,
    (constraints, impacts): (&mut [PointConstraint], &[PointImpact]),
    colors: &ContactColors,
    threshold: f64,
    h: f64,
) {
    // SAFETY: used on this thread only.
    let shared = unsafe { SharedBodies::new(&mut slots.slots) };
    for &k in &colors.position_of {
        let k = k as usize;
        restitute(&shared, (&mut constraints[k], &impacts[k]), threshold, h);
    }
}

/// Newton's restitution on contacts that were approaching faster than the threshold: the
/// outgoing normal speed becomes ε times the approach speed, as `rebound_speed` reads it
/// for the substeps of length `h`.
fn restitute(
    bodies: &SharedBodies,
    (c, impact): (&mut PointConstraint, &PointImpact),
    threshold: f64,
    h: f64,
) {
    let slow = impact.approach_speed > -threshold;
    if impact.restitution == 0.0 || slow || c.max_normal_impulse == 0.0 {
        return;
    }
    let gap = c.separation.max(0.0);
    let [normal_speed, _, _] = c.speeds(Portable, bodies);
    let delta = -c.normal_mass * (normal_speed - rebound_speed(impact, gap, h));
    let accumulated = (c.impulse.normal + delta).max(0.0);
    let applied = accumulated - c.impulse.normal;
    c.impulse.normal = accumulated;
    c.apply_normal(Portable, bodies, applied);
}

/// The normal speed a bounce leaves with, `gap` apart, under the relative acceleration a.
///
/// A substep (kick v += a h, then drift x += v h) conserves ½ (v + ½ a h)² − a·x exactly
/// under a constant a, x the position after the drift and v the velocity it drifted with:
/// the discrete arc rises and falls with the speed w = v + ½ a h, not v. The law is applied
/// to w, w_out = −ε w_in (the approach speed is kept as w); reflecting v instead would lose
/// (1 + ε)·½|a|h of launch speed at every bounce. The bodies leave from the end of the step, so v_out = w_out − ½ a h.
///
/// The speculative contact may stop the bodies short of each other: the last substep then
/// leaves a gap the next step would close. The rebound gets the speed it has at that gap,
/// √(w_out² + 2 a s) as `impact_speed` mirrored; leaving at the impact speed from above the
/// surface would add |a|·s of height.
fn rebound_speed(c: &PointImpact, gap: f64, h: f64) -> f64 {
    let a = c.approach_acceleration;
    let at_surface = -c.restitution * c.approach_speed;
    let at_gap = if a < 0.0 {
        (at_surface * at_surface + 2.0 * a * gap).max(0.0).sqrt()
    } else {
        at_surface
    };
    at_gap - 0.5 * a * h
}
