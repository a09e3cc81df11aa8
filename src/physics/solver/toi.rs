//! Time of impact.
//!
//! - `bisection_rewind`: the report's Algorithm 3 (section 3.2). Two bodies found
//!   penetrating at the end of a step are integrated backwards and forwards with sub-steps
//!   halved at every change of direction until they are apart by at most θ. Since the real
//!   integrator moves them, position, orientation and both momenta are rewound together.
//! - `conservative_advancement`: for fast bodies (section 4.3.1, tunnelling). From the start
//!   of the step, time advances by the current distance divided by a bound on the approach
//!   speed, so the bodies can never pass through each other between two samples.
//! - `swept_aabb`: the box holding everything a body sweeps during a step (the report's
//!   "volumes fantômes"), for the broad phase of the continuous test.

use glam::{DMat3, DQuat, DVec3};

use crate::physics::dynamics::body::RigidBody;
use crate::physics::dynamics::integrate::{Integrator, integrate_body};
use crate::physics::geometry::aabb::Aabb;
use crate::physics::geometry::gjk::{PosedShape, gjk_distance};

/// Sub-step halvings before the rewind gives up: 2⁻⁶⁰ of a step is far below round-off.
pub const REWIND_MAX_ITERATIONS: u32 = 60;

/// Where `bisection_rewind` left a pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rewind {
    /// Time within the step (s from its start) at which the bodies were left.
    pub time_of_impact: f64,
    /// Their distance then: in (0, θ] when `converged`.
    pub distance: f64,
    /// Distance tests made, at most `REWIND_MAX_ITERATIONS`.
    pub iterations: u32,
    /// False when the distance never fell in (0, θ]: the bodies are then left at the latest
    /// separated time found, or at the start of the step if they already overlapped there.
    pub converged: bool,
}

#[derive(Clone, Copy, PartialEq)]
enum Phase {
    Back,
    Forward,
}

/// The report's Algorithm 3. The bodies are at the end of a step of length `dt` and
/// penetrate; their force and torque accumulators must still hold the step's forces (the
/// report integrates with the same forces backwards). Afterwards both bodies are in their
/// contact configuration and `time_of_impact` says when within the step it happened.
pub fn bisection_rewind(
    a: &mut RigidBody,
    b: &mut RigidBody,
    dt: f64,
    theta: f64,
    integrator: Integrator,
) -> Rewind {
    let mut time = dt;
    let mut sub_step = dt;
    let mut phase = Phase::Back;
    let mut last_separated: Option<f64> = None;
    for iteration in 1..=REWIND_MAX_ITERATIONS {
        let distance = gjk_distance(a, b).distance;
        if distance > 0.0 {
            last_separated = Some(time);
            if distance <= theta {
                return rewind_result(time, distance, iteration, true);
            }
            if iteration == 1 {
                // Apart at the end of the step: there is no contact to rewind to.
                return rewind_result(time, distance, iteration, false);
            }
        }
        let next = if distance > 0.0 {
            Phase::Forward
        } else {
            Phase::Back
        };
        if next != phase || iteration == 1 {
            sub_step *= 0.5;
        }
        phase = next;
        let step = match phase {
            Phase::Back => -sub_step.min(time),
            Phase::Forward => sub_step,
        };
        if step == 0.0 {
            // Overlapping already at the start of the step: nothing earlier to go back to.
            return rewind_result(time, 0.0, iteration, false);
        }
        advance_pair(a, b, step, integrator);
        time += step;
    }
    settle_at_separated(a, b, time, last_separated, integrator)
}

fn rewind_result(time: f64, distance: f64, iterations: u32, converged: bool) -> Rewind {
    Rewind {
        time_of_impact: time,
        distance,
        iterations,
        converged,
    }
}

fn advance_pair(a: &mut RigidBody, b: &mut RigidBody, dt: f64, integrator: Integrator) {
    integrate_body(a, dt, integrator);
    integrate_body(b, dt, integrator);
}

/// Out of iterations: never leave the pair penetrating if a separated time is known.
fn settle_at_separated(
    a: &mut RigidBody,
    b: &mut RigidBody,
    time: f64,
    last_separated: Option<f64>,
    integrator: Integrator,
) -> Rewind {
    let target = last_separated.unwrap_or(time);
    advance_pair(a, b, target - time, integrator);
    let distance = gjk_distance(a, b).distance;
    rewind_result(target, distance, REWIND_MAX_ITERATIONS, false)
}

/// The pose of a body moving with constant linear and angular velocity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BallisticMotion {
    /// Centre of mass at t = 0, world, m.
    pub position: DVec3,
    /// Orientation at t = 0 (columns: the body's axes in world coordinates).
    pub orientation: DMat3,
    /// Velocity of the centre of mass, world, m/s.
    pub velocity: DVec3,
    /// Angular velocity, world, rad/s.
    pub angular_velocity: DVec3,
    /// Centre of mass in shape coordinates (see `RigidBody::local_center`).
    pub local_center: DVec3,
}

impl BallisticMotion {
    /// The body's current state; its velocities are held for the step.
    pub fn of_body(body: &RigidBody) -> Self {
        BallisticMotion {
            position: body.position,
            orientation: body.orientation,
            velocity: body.velocity(),
            angular_velocity: body.angular_velocity(),
            local_center: body.local_center,
        }
    }

    /// (shape origin, orientation) at time t.
    pub fn pose_at(&self, t: f64) -> (DVec3, DMat3) {
        let turn = DMat3::from_quat(DQuat::from_scaled_axis(self.angular_velocity * t));
        let orientation = turn * self.orientation;
        let center = self.position + self.velocity * t;
        (center - orientation * self.local_center, orientation)
    }
}

/// When and where `conservative_advancement` found two bodies within the tolerance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimeOfImpact {
    /// s from the start of the motion.
    pub time: f64,
    /// Distance between the shapes at `time` (≤ the requested tolerance).
    pub distance: f64,
    /// Unit, from A to B.
    pub normal: DVec3,
    /// The closest point on A at `time`, world.
    pub point_a: DVec3,
    /// The closest point on B at `time`, world.
    pub point_b: DVec3,
    /// Distance tests made, at most `ADVANCEMENT_MAX_ITERATIONS`.
    pub iterations: u32,
}

/// Advances before `conservative_advancement` gives up and reports no impact.
pub const ADVANCEMENT_MAX_ITERATIONS: u32 = 64;

/// The first time in [0, max_time] at which two bodies moving ballistically come within
/// `tolerance` of each other (returning at a distance in (0, tolerance] when they start
/// apart), or None if they do not. Each advance is the distance left divided by a bound on
/// the approach speed: the relative velocity along the normal plus |ω| times the largest
/// distance from the centre of mass to the surface, for each body.
pub fn conservative_advancement(
    a: &RigidBody,
    b: &RigidBody,
    max_time: f64,
    tolerance: f64,
) -> Option<TimeOfImpact> {
    let (motion_a, motion_b) = (BallisticMotion::of_body(a), BallisticMotion::of_body(b));
    let reach_a = a.shape.bounding_radius() + a.local_center.length();
    let reach_b = b.shape.bounding_radius() + b.local_center.length();
    let spin_bound =
        motion_a.angular_velocity.length() * reach_a + motion_b.angular_velocity.length() * reach_b;
    let mut time = 0.0;
    for iteration in 1..=ADVANCEMENT_MAX_ITERATIONS {
        let (origin_a, rotation_a) = motion_a.pose_at(time);
        let (origin_b, rotation_b) = motion_b.pose_at(time);
        let shape_a = PosedShape::new(&a.shape, origin_a, rotation_a);
        let shape_b = PosedShape::new(&b.shape, origin_b, rotation_b);
        let gjk = gjk_distance(&shape_a, &shape_b);
        if gjk.distance <= tolerance {
            return Some(TimeOfImpact {
                time,
                distance: gjk.distance,
                normal: gjk.normal,
                point_a: gjk.point_a,
                point_b: gjk.point_b,
                iterations: iteration,
            });
        }
        let approach = (motion_a.velocity - motion_b.velocity).dot(gjk.normal);
        let speed_bound = approach.max(0.0) + spin_bound;
        if speed_bound <= 0.0 {
            return None;
        }
        // Aim at half the tolerance so the last sample lands inside (0, tolerance].
        time += (gjk.distance - 0.5 * tolerance) / speed_bound;
        if time > max_time {
            return None;
        }
    }
    None
}

/// A box holding the body over a step of length `dt` at its current velocities: the box
/// swept by the translation, grown by how far rotation can move a surface point (|ω| dt
/// times the reach from the centre of mass, at most the reach's diameter).
pub fn swept_aabb(body: &RigidBody, dt: f64) -> Aabb {
    let reach = body.shape.bounding_radius() + body.local_center.length();
    let turn = (body.angular_velocity().length() * dt.abs()).min(2.0);
    Aabb::of_body(body)
        .swept(body.velocity() * dt)
        .fattened(reach * turn)
}
