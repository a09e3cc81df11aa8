//! The `classic` pipeline: the report's method (sections 3 and 4.1).
//!
//! `Ordered` (the report's Algorithm 5, the default): forces first update every momentum for
//! the whole step (L += F dt, A += τ dt, as the report integrates), then time is swept in
//! events with constant momenta. Free flight is therefore first order in dt (a bounce apex
//! is short by g·dt/v of its height); `substeps` splits the step to reduce that. Each event:
//! 1. resolves the pairs that touch now (within θ) with Newton's restitution impulse
//!    (ε the smaller of the two, forced to 0 when the approach is slower than
//!    `resting_speed`: a resting contact), plus Coulomb friction;
//! 2. predicts every other candidate pair over the time left: copies of both bodies are
//!    advanced, and a pair that ends up penetrating is rewound by bisection (Algorithm 3) to
//!    its time of impact; a pair fast enough to pass through in one go is caught by
//!    conservative advancement (section 4.3.1, tunnelling);
//! 3. advances every body to the earliest time of impact, where the next event starts.
//!
//! Touching pairs are resolved before prediction because a resting contact would otherwise
//! have a time of impact of zero at every event and the loop would never end (the report
//! meets the same difficulty and answers it with ε = 0 impulses and sleeping).
//!
//! `Simple` (Algorithm 4, for comparison), in the report's order: pairs penetrating at the
//! start of the step are rewound to their contact configuration (momenta with the poses),
//! impulses are applied, then the environment forces act and every body takes the whole
//! step. It depends on the order of the pairs, as the report explains. Its free flight is
//! semi-implicit Euler with nothing to offset the error: with the report's one slice at
//! dt = 1/60 every C2 apex comes out low, each bounce lower than the last, and C2 is missed;
//! the error shrinks with the slice, and 24 slices meet C2 (`tests/classic.rs`;
//! BENCHMARKS.md, "Simple loop apexes").
//!
//! Several contacts of one event are solved together by repeating the impulses
//! (`iterations`), each clamped so that bodies are never pulled together; with one contact
//! the first pass is exactly the report's formula.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::physics::collision::broad_phase::BodyPair;
use crate::physics::collision::contact::ContactManifold;
use crate::physics::collision::manifold::contact_manifold;
use crate::physics::dynamics::body::RigidBody;
use crate::physics::dynamics::forces::{self, EnvironmentForce};
use crate::physics::dynamics::integrate::{self, Integrator};
use crate::physics::geometry::gjk::gjk_distance;
use crate::physics::solver::impulse::{Arms, clamp_to_friction_disc, tangent_basis};
use crate::physics::solver::toi::{bisection_rewind, conservative_advancement};

/// How a classic step orders impacts in time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum MainLoop {
    /// Algorithm 4: correct, respond, then integrate everyone by dt.
    Simple,
    /// Algorithm 5: advance everyone to the earliest time of impact, resolve, repeat.
    #[default]
    Ordered,
}

/// Settings of the `classic` pipeline.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ClassicSettings {
    /// Which of the report's main loops runs.
    pub main_loop: MainLoop,
    /// Contact tolerance θ, m: bodies closer than this touch; the rewind stops within it.
    pub theta: f64,
    /// Approach speeds below this get ε = 0 (resting contacts), m/s.
    pub resting_speed: f64,
    /// Impulse passes over the contacts of one event.
    pub iterations: u32,
    /// Events per step before the rest of the step is taken without ordering.
    pub max_events: u32,
    /// Slices of the step, each with its own forces and event sweep (1: the report's).
    pub substeps: u32,
}

impl Default for ClassicSettings {
    fn default() -> Self {
        ClassicSettings {
            main_loop: MainLoop::Ordered,
            theta: 1e-4,
            resting_speed: 0.5,
            iterations: 20,
            max_events: 64,
            substeps: 1,
        }
    }
}

/// Counters of one classic step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ClassicReport {
    /// Events over all slices (`Simple`: one per slice).
    pub events: u32,
    /// Bisection rewinds run, over all slices.
    pub rewinds: u32,
    /// True when `max_events` cut the ordering short.
    pub events_exhausted: bool,
}

/// Everything a classic step needs besides the bodies and candidate pairs.
#[derive(Clone, Copy)]
pub struct ClassicContext<'a> {
    /// The world's environmental forces.
    pub forces: &'a [EnvironmentForce],
    /// How poses are advanced.
    pub integrator: Integrator,
    /// The pipeline's settings.
    pub settings: &'a ClassicSettings,
    /// The step, s.
    pub dt: f64,
}

/// Advances the bodies by `ctx.dt`. `pairs` are the broad phase's candidates for the step.
/// Returns the counters and the manifolds resolved at the last event (for display).
///
/// The forces and torques users put on the bodies act over the whole step: each slice
/// clears them once it has applied them (so that its predictions move bodies
/// ballistically), so they are held in `loads` (a list kept between steps, so that it
/// allocates once) and put back before the next slice.
pub fn step(
    bodies: &mut [RigidBody],
    pairs: &[BodyPair],
    ctx: &ClassicContext,
    loads: &mut Vec<[DVec3; 2]>,
) -> (ClassicReport, Vec<ContactManifold>) {
    let slices = ctx.settings.substeps.max(1);
    let slice = ClassicContext {
        dt: ctx.dt / slices as f64,
        ..*ctx
    };
    loads.clear();
    loads.extend(bodies.iter().map(|body| [body.force, body.torque]));
    let mut total = ClassicReport::default();
    let mut touching = Vec::new();
    for index in 0..slices {
        if index > 0 {
            for (body, &[force, torque]) in bodies.iter_mut().zip(loads.iter()) {
                (body.force, body.torque) = (force, torque);
            }
        }
        let (report, last) = match ctx.settings.main_loop {
            MainLoop::Ordered => {
                apply_forces(bodies, ctx.forces, slice.dt);
                ordered_step(bodies, pairs, &slice)
            }
            MainLoop::Simple => simple_step(bodies, pairs, &slice),
        };
        total.events += report.events;
        total.rewinds += report.rewinds;
        total.events_exhausted |= report.events_exhausted;
        touching = last;
    }
    (total, touching)
}

/// L += F dt and A += τ dt for every awake body; the accumulators are then cleared so that
/// the ordered loop's predictions and rewinds move bodies ballistically.
fn apply_forces(bodies: &mut [RigidBody], environment: &[EnvironmentForce], dt: f64) {
    for body in bodies.iter_mut() {
        if body.is_awake() {
            forces::apply_environment(environment, body);
            integrate::integrate_momenta(body, dt);
        }
        body.clear_accumulators();
    }
}

fn ordered_step(
    bodies: &mut [RigidBody],
    pairs: &[BodyPair],
    ctx: &ClassicContext,
) -> (ClassicReport, Vec<ContactManifold>) {
    let mut report = ClassicReport::default();
    let mut remaining = ctx.dt;
    let mut touching = Vec::new();
    while remaining > 0.0 {
        touching = touching_manifolds(bodies, pairs, ctx.settings.theta);
        resolve(bodies, &touching, ctx.settings);
        report.events += 1;
        if report.events >= ctx.settings.max_events {
            report.events_exhausted = true;
            advance(bodies, remaining, ctx.integrator);
            break;
        }
        let impact = earliest_impact(bodies, pairs, remaining, ctx, &mut report);
        let advance_by = impact.unwrap_or(remaining).min(remaining);
        advance(bodies, advance_by, ctx.integrator);
        remaining -= advance_by;
        if impact.is_none() {
            break;
        }
    }
    (report, touching)
}

/// Algorithm 4 in the report's order: collisions are corrected and answered first, then the
/// environment forces act and every body is integrated. Forces applied before the response
/// would be rewound with the poses and would add a step of gravity to every impact speed.
fn simple_step(
    bodies: &mut [RigidBody],
    pairs: &[BodyPair],
    ctx: &ClassicContext,
) -> (ClassicReport, Vec<ContactManifold>) {
    let mut report = ClassicReport::default();
    for pair in pairs {
        let (a, b) = pair_mut(bodies, pair);
        if gjk_distance(a, b).distance == 0.0 {
            rewind_along_last_step(a, b, ctx);
            report.rewinds += 1;
        }
    }
    let touching = touching_manifolds(bodies, pairs, ctx.settings.theta);
    resolve(bodies, &touching, ctx.settings);
    apply_forces(bodies, ctx.forces, ctx.dt);
    advance(bodies, ctx.dt, ctx.integrator);
    report.events = 1;
    (report, touching)
}

/// Algorithm 3 back along the step the pair just took, with that step's environment forces
/// so that the momenta are rewound with the poses (a ballistic rewind would lift a falling
/// body to the contact at its impact speed, creating energy). The forces the user put on
/// the bodies for this step are kept aside meanwhile.
fn rewind_along_last_step(a: &mut RigidBody, b: &mut RigidBody, ctx: &ClassicContext) {
    let kept = [(a.force, a.torque), (b.force, b.torque)];
    for body in [&mut *a, &mut *b] {
        body.clear_accumulators();
        forces::apply_environment(ctx.forces, body);
    }
    bisection_rewind(a, b, ctx.dt, ctx.settings.theta, ctx.integrator);
    [(a.force, a.torque), (b.force, b.torque)] = kept;
}

fn pair_mut<'a>(
    bodies: &'a mut [RigidBody],
    pair: &BodyPair,
) -> (&'a mut RigidBody, &'a mut RigidBody) {
    let (low, high) = (pair.a.index(), pair.b.index());
    let (head, tail) = bodies.split_at_mut(high);
    (&mut head[low], &mut tail[0])
}

/// Poses move with the current momenta; the forces were applied once for the whole step.
fn advance(bodies: &mut [RigidBody], time: f64, integrator: Integrator) {
    if time <= 0.0 {
        return;
    }
    for body in bodies.iter_mut().filter(|b| b.is_awake()) {
        integrate::integrate_pose(body, time, integrator);
    }
}

/// The manifolds of candidate pairs within 2θ of each other, with at least one awake body.
fn touching_manifolds(
    bodies: &[RigidBody],
    pairs: &[BodyPair],
    theta: f64,
) -> Vec<ContactManifold> {
    pairs
        .iter()
        .filter(|p| bodies[p.a.index()].is_awake() || bodies[p.b.index()].is_awake())
        .filter_map(|p| {
            contact_manifold(
                &bodies[p.a.index()],
                p.a,
                &bodies[p.b.index()],
                p.b,
                2.0 * theta,
            )
        })
        .collect()
}

/// The earliest time of impact, within `horizon`, of the candidate pairs that do not touch now.
fn earliest_impact(
    bodies: &[RigidBody],
    pairs: &[BodyPair],
    horizon: f64,
    ctx: &ClassicContext,
    report: &mut ClassicReport,
) -> Option<f64> {
    let theta = ctx.settings.theta;
    let mut earliest: Option<f64> = None;
    for pair in pairs {
        let (a, b) = (&bodies[pair.a.index()], &bodies[pair.b.index()]);
        if !(a.is_awake() || b.is_awake()) || gjk_distance(a, b).distance <= 2.0 * theta {
            continue;
        }
        let (mut a2, mut b2) = (a.clone(), b.clone());
        advance_copy(&mut a2, horizon, ctx.integrator);
        advance_copy(&mut b2, horizon, ctx.integrator);
        let time = if gjk_distance(&a2, &b2).distance == 0.0 {
            report.rewinds += 1;
            Some(bisection_rewind(&mut a2, &mut b2, horizon, theta, ctx.integrator).time_of_impact)
        } else {
            // Apart at both ends; a fast pair may still have crossed in between.
            conservative_advancement(a, b, horizon, theta).map(|toi| toi.time)
        };
        if let Some(t) = time {
            earliest = Some(earliest.map_or(t, |e: f64| e.min(t)));
        }
    }
    earliest
}

fn advance_copy(body: &mut RigidBody, time: f64, integrator: Integrator) {
    if body.is_awake() {
        integrate::integrate_pose(body, time, integrator);
    }
}

/// One contact point of an event, with what the impulses need.
struct ImpactPoint {
    arms: Arms,
    normal: DVec3,
    tangents: [DVec3; 2],
    normal_mass: f64,
    tangent_mass: [f64; 2],
    /// Normal relative speed wanted after the impact: −ε times the approach speed, or 0.
    target_speed: f64,
    friction: f64,
    normal_impulse: f64,
    tangent_impulse: [f64; 2],
}

/// Newton's restitution impulses, with friction, over all contacts of the event.
fn resolve(bodies: &mut [RigidBody], manifolds: &[ContactManifold], settings: &ClassicSettings) {
    let mut points: Vec<ImpactPoint> = manifolds
        .iter()
        .flat_map(|m| m.contacts.iter().map(move |c| (m, c)))
        .map(|(m, c)| {
            impact_point(
                bodies,
                m.body_a.index(),
                m.body_b.index(),
                c.position,
                c.normal,
                settings,
            )
        })
        .collect();
    for _ in 0..settings.iterations.max(1) {
        for point in points.iter_mut() {
            solve_point(bodies, point);
        }
    }
}

fn impact_point(
    bodies: &[RigidBody],
    a: usize,
    b: usize,
    position: DVec3,
    normal: DVec3,
    settings: &ClassicSettings,
) -> ImpactPoint {
    let (body_a, body_b) = (&bodies[a], &bodies[b]);
    let arms = Arms::at(bodies, a, b, position);
    let approach = normal.dot(arms.relative_velocity(bodies));
    let restitution = body_a.material.restitution.min(body_b.material.restitution);
    let target_speed = if approach < -settings.resting_speed {
        -restitution * approach
    } else {
        0.0
    };
    let tangents = tangent_basis(normal);
    ImpactPoint {
        arms,
        normal,
        tangents,
        // The report's impulse J = −(1 + ε) v_r / denominator is this mass times the change
        // of normal speed, from v_r to −ε v_r.
        normal_mass: arms.effective_mass(bodies, normal),
        tangent_mass: [
            arms.effective_mass(bodies, tangents[0]),
            arms.effective_mass(bodies, tangents[1]),
        ],
        target_speed,
        friction: (body_a.material.friction * body_b.material.friction).sqrt(),
        normal_impulse: 0.0,
        tangent_impulse: [0.0; 2],
    }
}

/// The accumulated normal impulse reaches the target speed and never pulls; friction stays
/// inside the Coulomb disc of radius μ times the normal impulse.
fn solve_point(bodies: &mut [RigidBody], p: &mut ImpactPoint) {
    let normal_speed = p.normal.dot(p.arms.relative_velocity(bodies));
    let total = (p.normal_impulse + p.normal_mass * (p.target_speed - normal_speed)).max(0.0);
    let applied = total - p.normal_impulse;
    p.normal_impulse = total;
    p.arms.apply(bodies, p.normal * applied);

    let slip = p.arms.relative_velocity(bodies);
    let unclamped = [
        p.tangent_impulse[0] - p.tangent_mass[0] * p.tangents[0].dot(slip),
        p.tangent_impulse[1] - p.tangent_mass[1] * p.tangents[1].dot(slip),
    ];
    let tangent = clamp_to_friction_disc(unclamped, p.friction * p.normal_impulse);
    let change = p.tangents[0] * (tangent[0] - p.tangent_impulse[0])
        + p.tangents[1] * (tangent[1] - p.tangent_impulse[1]);
    p.tangent_impulse = tangent;
    p.arms.apply(bodies, change);
}
