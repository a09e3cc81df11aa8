//! The `soft` contact solver: substepped sequential impulses on soft constraints.
//!
//! A step reads as its stages (`step`):
//!
//! 1. **prepare** (`prepare`): each awake body gets a solver slot, the contacts are coloured
//!    and each contact point becomes a constraint (anchors, tangents, effective masses); the
//!    impulses remembered from the last step are gathered as the first **warm start**.
//!    The joints are prepared alongside (`joints::solve`).
//! 2. each substep of length h = dt / substeps:
//!    **integrate velocities** (forces) and apply the **warm start** (the joints' along
//!    their directions at the substep's poses, held by the last relax pass) →
//!    **solve** the joints, then the contacts, with a soft position bias (`solve`) →
//!    in a step with deep overlaps, **push-out** (`push_out`) → **integrate positions** →
//!    **relax**: solve joints and contacts again without bias,
//!    removing the velocity the bias added → keep what the joints and contacts gave each
//!    body as the next substep's warm start.
//! 3. **restitution** (`restitution`): one pass gives fast impacts their bounce.
//! 4. **store impulses**: the momenta go back to the bodies, and `SoftScratch::impulses`
//!    hands each contact's final impulse to the world's contact memory for the next step.
//!
//! Softness: a penetration is not removed in one substep (which makes stacks jitter) but
//! pulled out like a critically-damped spring of `contact_hertz` Hz, capped at
//! `max_push_out` m/s. An overlap much deeper than a contact's load explains (bodies
//! created inside each other) is instead pushed out by moving the bodies apart, at most
//! `max_push_out` fast, while its velocity is solved rigidly (`push_out`). A contact
//! that is still open (positive separation: speculative) lets the bodies close the gap in
//! this substep and no more, which stops fast bodies short of the surface without adding
//! energy.
//!
//! The solver works on the bodies' momenta (the report's state): velocities are derived
//! from them at every use, so a rotating body keeps its angular momentum exactly.
//!
//! Material combination: restitution is the smaller of the two (as in the report), friction
//! the geometric mean √(μa μb).

mod constraint;
mod prepare;
mod push_out;
mod restitution;
mod solve;
#[cfg(test)]
mod tests;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::physics::dynamics::body::RigidBody;
use crate::physics::dynamics::forces::{self, EnvironmentForce};
use crate::physics::dynamics::integrate::{self, Integrator};
use crate::physics::joints::joint::Joint;
use crate::physics::joints::rows::RowPass;
use crate::physics::joints::solve::{self as joint_solve, JointConstraint, NextSubstep};
use crate::physics::solver::contact_colors::ContactColors;
#[cfg(target_arch = "x86_64")]
use crate::physics::solver::lanes::Avx2;
use crate::physics::solver::lanes::{Lanes, Portable};
use crate::physics::solver::solver_bodies::{SolverBodies, SpinGuard};
use crate::physics::stage_times::timed;
use constraint::{Contacts, PointAnchors, PointConstraint, PointImpact};
use prepare::SlotMotion;
use solve::Pass;
pub(crate) use solve::Softness;

/// A contact point handed to the solver. The normal points from body `a` to body `b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactInput {
    /// Index of the first body in the body list.
    pub a: usize,
    /// Index of the second body in the body list.
    pub b: usize,
    /// Where the impulses act on `a` and on `b`: lever arms from their centres of mass,
    /// world axes (`Contact::levers`).
    pub levers: [DVec3; 2],
    /// Unit contact normal, world, from `a` to `b`.
    pub normal: DVec3,
    /// Distance between the surfaces along the normal; negative when penetrating.
    pub separation: f64,
    /// Normal and friction impulses this point ended the last step with.
    pub warm_impulse: WarmImpulse,
}

/// Accumulated impulses per substep, kept across steps for warm starting.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WarmImpulse {
    /// Along the normal, N·s (never negative: contacts only push).
    pub normal: f64,
    /// Along the contact's two tangents, N·s.
    pub tangent: [f64; 2],
}

/// Settings of the `soft` pipeline.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SoftSolverSettings {
    /// Substeps per step (at least 1): more is stiffer and more accurate, and costs more.
    pub substeps: u32,
    /// Stiffness of the contact spring, Hz (capped at a fifth of the substep rate).
    pub contact_hertz: f64,
    /// Damping ratio of the contact spring (>1: overdamped, no bounce from push-out).
    pub damping_ratio: f64,
    /// Fastest speed at which overlap is pushed out, m/s.
    pub max_push_out: f64,
    /// Overlap deeper than this beyond what a contact's load explains (bodies created
    /// inside each other), m, is pushed out by moving the bodies, at most `max_push_out`
    /// fast each, rather than through their velocities, which carried the push on through a
    /// crowd of such bodies and flung them apart. Bullet's split impulse starts at the same
    /// depth.
    pub deep_overlap: f64,
    /// Approach speeds below this do not bounce (resting contacts), m/s.
    pub restitution_threshold: f64,
    /// Stiffness of the joints' spring, Hz: how fast a joint pulls its bodies back together
    /// (capped at a quarter of the substep rate: a weld rang apart at half).
    pub joint_hertz: f64,
    /// Damping ratio of the joints' spring.
    pub joint_damping_ratio: f64,
}

impl Default for SoftSolverSettings {
    fn default() -> Self {
        SoftSolverSettings {
            // A loaded contact settles by (load / effective mass)·g/ω², so the spring is as
            // stiff as the substeps carry without ringing: the cap (a fifth of the substep
            // rate) is 96 Hz for 8 substeps at dt = 1/60, and 60 Hz is not cut.
            substeps: 8,
            contact_hertz: 60.0,
            damping_ratio: 10.0,
            max_push_out: 3.0,
            deep_overlap: 0.04,
            restitution_threshold: 1.0,
            joint_hertz: JOINT_HERTZ,
            joint_damping_ratio: JOINT_DAMPING_RATIO,
        }
    }
}

/// `SoftSolverSettings::joint_hertz` by default, which the cap (a quarter of the substep
/// rate) makes 120 Hz at 8 substeps of 1/60 s and 240 Hz at 16: at 8 substeps a swinging
/// chain of 20 links stretched 2.8 mm at a joint at 60 Hz and 0.9 mm at 120 Hz
/// (tests/joints.rs).
pub const JOINT_HERTZ: f64 = 240.0;
/// `SoftSolverSettings::joint_damping_ratio` by default.
pub const JOINT_DAMPING_RATIO: f64 = 5.0;

/// Everything one soft step needs besides the bodies and contacts.
pub struct StepContext<'a> {
    /// The world's environmental forces.
    pub forces: &'a [EnvironmentForce],
    /// How poses are advanced in each substep.
    pub integrator: Integrator,
    /// The solver's settings.
    pub settings: &'a SoftSolverSettings,
    /// The step, s.
    pub dt: f64,
    /// Whether to measure `SoftStep::integrate_seconds` (it reads the clock per substep).
    pub timed: bool,
}

/// What a soft step hands back.
pub struct SoftStep {
    /// Seconds spent on forces and integration, over all substeps (for the stage profile);
    /// 0 unless the step was `timed`.
    pub integrate_seconds: f64,
}

/// Buffers a soft step keeps for the next one, so that stepping allocates nothing once
/// they have grown to the scene.
#[derive(Clone, Debug, Default)]
pub struct SoftScratch {
    /// In colour order (see `contact_colors`).
    constraints: Vec<PointConstraint>,
    /// The constraints' anchors, in the same order.
    anchors: Vec<PointAnchors>,
    /// What restitution reads of them, in the same order.
    impacts: Vec<PointImpact>,
    colors: ContactColors,
    user_forces: Vec<(DVec3, DVec3)>,
    /// Each slot's body's motion at step start.
    motions: Vec<SlotMotion>,
    bodies: SolverBodies,
    joints: Vec<JointConstraint>,
    /// The bodies whose spin the substeps limit (`spin_guards`).
    spin_guards: SpinGuards,
    /// What the push-out keeps in a step with deep points (`push_out`).
    push_out: push_out::PushOutScratch,
}

impl SoftScratch {
    /// The impulses each contact ended the last step with (in the order of its contacts),
    /// for warm starting.
    pub fn impulses(&self) -> impl Iterator<Item = WarmImpulse> + '_ {
        let constraints = &self.constraints;
        (self.colors.position_of.iter()).map(move |&k| constraints[k as usize].impulse)
    }
}

/// Advances the `awake` bodies (ascending indices into `bodies`) by one step of `ctx.dt` with
/// the given contacts and joints. No other body is visited, and only the joints are that
/// hold an awake body.
///
/// Compiled a second time for processors with AVX2, as the passes are (`solve`): the
/// preparation of the contacts is plain vector arithmetic that the wider instructions
/// carry with fewer moves between registers. Both compute the same bits: neither fuses a
/// multiply with an add.
pub fn step(
    bodies: &mut [RigidBody],
    awake: &[u32],
    contacts: &[ContactInput],
    joints: &mut [Option<Joint>],
    ctx: &StepContext,
    scratch: &mut SoftScratch,
) -> SoftStep {
    #[cfg(target_arch = "x86_64")]
    if let Some(avx) = Avx2::detect() {
        // SAFETY: the processor has AVX2, as `avx` proves.
        return unsafe { step_avx2(avx, bodies, awake, contacts, joints, ctx, scratch) };
    }
    step_inline(Portable, bodies, awake, contacts, joints, ctx, scratch)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn step_avx2(
    avx: Avx2,
    bodies: &mut [RigidBody],
    awake: &[u32],
    contacts: &[ContactInput],
    joints: &mut [Option<Joint>],
    ctx: &StepContext,
    scratch: &mut SoftScratch,
) -> SoftStep {
    step_inline(avx, bodies, awake, contacts, joints, ctx, scratch)
}

/// The body of `step`, compiled into each of its variants: one call per stage.
#[inline(always)]
fn step_inline<L: Lanes>(
    l: L,
    bodies: &mut [RigidBody],
    awake: &[u32],
    contacts: &[ContactInput],
    joints: &mut [Option<Joint>],
    ctx: &StepContext,
    scratch: &mut SoftScratch,
) -> SoftStep {
    prepare::prepare_contacts(l, bodies, awake, contacts, ctx, scratch);
    joint_solve::prepare(&mut scratch.joints, joints, bodies, &scratch.bodies);
    keep_user_forces(&mut scratch.user_forces, bodies, awake);
    let SoftScratch {
        constraints,
        anchors,
        impacts,
        colors,
        user_forces,
        bodies: slots,
        joints: joint_constraints,
        spin_guards: guards,
        push_out,
        ..
    } = scratch;
    let substeps = ctx.settings.substeps.max(1);
    let h = ctx.dt / substeps as f64;
    let max_spin = MAX_TURN_IN_CONTACT / h;
    spin_guards(guards, bodies, awake, max_spin);
    let softness = Softness::of_contacts(ctx.settings, h);
    let max_push_out = ctx.settings.max_push_out;
    let deep_overlap = ctx.settings.deep_overlap;
    let deep_points = begins_deep(contacts, deep_overlap)
        && push_out::mark_deep(constraints, softness, deep_overlap);
    if deep_points {
        push_out::prepare(push_out, (bodies, awake), slots.slots.len(), constraints);
    }
    let biased = Pass::Biased {
        softness,
        max_push_out,
        deep_points,
    };
    let joints_biased = RowPass {
        softness: Some(Softness::of_joints(ctx.settings, h)),
        h,
    };
    let joints_relax = RowPass { softness: None, h };
    joint_solve::hold_first_warm_start(joint_constraints, &mut slots.slots, bodies);
    let mut integrate_seconds = 0.0;
    for substep in 0..substeps {
        let next = if substep + 1 < substeps {
            NextSubstep::WarmStart
        } else {
            NextSubstep::None
        };
        timed(ctx.timed, &mut integrate_seconds, || {
            slots.integrate_velocities_and_warm_start(bodies, |k, body| {
                (body.force, body.torque) = user_forces[k];
                forces::apply_environment(ctx.forces, body);
                integrate::integrate_momenta(body, h);
            })
        });
        let (joint_slots, none) = (&mut slots.slots, NextSubstep::None);
        joint_solve::solve_all(joint_constraints, joint_slots, bodies, joints_biased, none);
        let mut contacts = Contacts {
            points: constraints,
            anchors,
            impacts,
        };
        solve::for_each_contact(&mut slots.slots, &mut contacts, colors, biased, h);
        if deep_points {
            push_out::solve(&mut slots.slots, contacts.points, max_push_out, push_out, h);
        }
        slots.limit_spins(bodies, &guards.list, max_spin);
        timed(ctx.timed, &mut integrate_seconds, || {
            let push_out_limit = (max_push_out, h);
            slots.integrate_positions(bodies, push_out_limit, |body| {
                integrate::integrate_pose(body, h, ctx.integrator)
            })
        });
        joint_solve::solve_all(
            joint_constraints,
            &mut slots.slots,
            bodies,
            joints_relax,
            next,
        );
        solve::for_each_contact(&mut slots.slots, &mut contacts, colors, Pass::Relax, h);
        slots.limit_spins(bodies, &guards.list, max_spin);
        slots.store_warm_start(bodies, substep + 1 < substeps);
    }
    let threshold = ctx.settings.restitution_threshold;
    restitution::apply_restitution(slots, (constraints, impacts), colors, threshold, h);
    slots.limit_spins(bodies, &guards.list, max_spin);
    joint_solve::finish(joint_constraints, &slots.slots, bodies, joints, h);
    slots.write_back(bodies);
    slots.release();
    for &index in awake {
        bodies[index as usize].clear_accumulators();
    }
    SoftStep { integrate_seconds }
}

/// Whether a contact begins the step deeper than `deep_overlap`: only then can a point be
/// deep (`push_out::mark_deep`).
fn begins_deep(contacts: &[ContactInput], deep_overlap: f64) -> bool {
    contacts.iter().any(|c| c.separation < -deep_overlap)
}

/// The most a body in contact may turn in one substep, rad: a contact cannot follow a body
/// turning further (a thin rod spun about its axis by a glancing hit gained energy without
/// bound); free bodies keep any spin. Box2D limits every body the same way.
const MAX_TURN_IN_CONTACT: f64 = 0.25 * std::f64::consts::PI;

/// Lists each awake body that a contact point touches (`SpinGuards::touched`, filled by
/// `prepare_contacts`) and momentum spins (not kinematic), with the angular momentum below
/// which it cannot spin faster than `max_spin`: that spin over trace(I⁻¹), which bounds the
/// largest spin a momentum gives and does not change as the body turns. The substeps'
/// checks then read no body but the few near the limit, and visit none in a scene without
/// contacts.
fn spin_guards(guards: &mut SpinGuards, bodies: &[RigidBody], awake: &[u32], max_spin: f64) {
    let SpinGuards { touched, list } = guards;
    list.clear();
    for (k, (&touches, &index)) in touched.iter().zip(awake).enumerate() {
        let body = &bodies[index as usize];
        if touches && !body.is_kinematic() {
            let m = body.inv_inertia_local;
            list.push(SpinGuard {
                slot: k as u32 + 1,
                momentum: max_spin / (m.x_axis.x + m.y_axis.y + m.z_axis.z),
            });
        }
    }
}

/// `spin_guards`' lists, kept between steps.
#[derive(Clone, Debug, Default)]
struct SpinGuards {
    /// Whether a contact point touches each awake body (by its place in `awake`).
    touched: Vec<bool>,
    /// The touched bodies that momentum spins, in slot order.
    list: Vec<SpinGuard>,
}

/// The forces the user applied before the step, which act over all of it like the
/// environment's (the substeps clear the bodies' accumulators).
fn keep_user_forces(kept: &mut Vec<(DVec3, DVec3)>, bodies: &[RigidBody], awake: &[u32]) {
    kept.clear();
    kept.extend(awake.iter().map(|&i| {
        let body = &bodies[i as usize];
        (body.force, body.torque)
    }));
}
