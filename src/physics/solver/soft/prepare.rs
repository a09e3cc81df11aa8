//! Preparation, once per step: solver slots for the awake bodies, the contacts' colours, and
//! each contact point as a `PointConstraint` (anchors, tangents, effective masses, the
//! fastest approach it may bounce); then the first warm start from the impulses the contacts
//! ended the last step with.

use glam::DVec3;

use super::constraint::{
    PointAnchors, PointConstraint, PointImpact, SideGeometry, inv_mass, load3, moves,
};
use super::{ContactInput, SoftScratch, SpinGuards, StepContext};
use crate::physics::dynamics::body::RigidBody;
use crate::physics::dynamics::forces::EnvironmentForce;
use crate::physics::solver::impulse::tangent_basis;
use crate::physics::solver::lanes::{F32x4, F64x4, LaneVector, Lanes, prefetch, rounded_to_f32};
use crate::physics::solver::solver_bodies::{FIXED_SLOT, SolverBodies};

/// Gives each awake body a slot, colours the contacts (see `contact_colors`) and prepares
/// every contact point as a constraint, in colour order; then the first warm start from the
/// impulses the contacts ended the last step with, added up per body, and which bodies a
/// contact touches (`SpinGuards::touched`).
///
/// One loop in colour order does it all, so that the records, larger together than the
/// processor's caches, are written once, one after the other, and read again while still in
/// cache (BENCHMARKS.md, "Preparation in one pass").
#[inline(always)]
pub(super) fn prepare_contacts<L: Lanes>(
    l: L,
    bodies: &[RigidBody],
    awake: &[u32],
    contacts: &[ContactInput],
    ctx: &StepContext,
    scratch: &mut SoftScratch,
) {
    let SoftScratch {
        constraints,
        anchors,
        impacts,
        colors,
        motions,
        bodies: slots,
        spin_guards: SpinGuards { touched, .. },
        ..
    } = scratch;
    slots.assign(bodies, awake);
    let contact_slots = contacts
        .iter()
        .map(|c| [slots.slot_of(c.a), slots.slot_of(c.b)]);
    colors.assign(contact_slots, slots.count(), FIXED_SLOT);
    SlotMotion::gather(motions, bodies, awake, ctx.forces);
    touched.clear();
    touched.resize(awake.len(), false);
    // Written in place: collecting would build each (large) constraint aside and copy it.
    constraints.resize(colors.order.len(), PointConstraint::default());
    anchors.resize(colors.order.len(), PointAnchors::default());
    impacts.resize(colors.order.len(), PointImpact::default());
    // A manifold's points share their normal, and so their tangents, and stay together in
    // colour order.
    let mut basis = (DVec3::NAN, [DVec3::NAN; 2]);
    let order = &colors.order;
    for (k, &index) in order.iter().enumerate() {
        prefetch_ahead(contacts, bodies, order, k);
        let contact = &contacts[index as usize];
        if contact.normal != basis.0 {
            basis = (contact.normal, tangent_basis(contact.normal));
        }
        (constraints[k], anchors[k], impacts[k]) =
            prepare(l, bodies, slots, contact, basis.1, motions, ctx.dt);
        let constraint = &constraints[k];
        slots.add_warm_start(l, constraint.warm_start_pushes(l));
        for slot in constraint.slots {
            if let Some(place) = (slot as usize).checked_sub(1) {
                touched[place] = true;
            }
        }
        pair_with_previous(constraints, k);
    }
}

/// How many contacts ahead, in colour order, `prepare_contacts` asks for a contact, and
/// half as many for its bodies (whose indices it reads from the contact asked for before).
const PREFETCH_AHEAD: usize = 16;

/// Asks the processor for what the contacts ahead will read: colour order takes the contacts,
/// and so their bodies, in a jumbled order, and each read missed the caches.
#[inline(always)]
fn prefetch_ahead(contacts: &[ContactInput], bodies: &[RigidBody], order: &[u32], k: usize) {
    if let Some(&ahead) = order.get(k + PREFETCH_AHEAD) {
        prefetch(&contacts[ahead as usize]);
    }
    if let Some(&near) = order.get(k + PREFETCH_AHEAD / 2) {
        let contact = &contacts[near as usize];
        prefetch(&bodies[contact.a]);
        prefetch(&bodies[contact.b]);
    }
}

/// What the preparation reads of a moving body, computed once per body rather than at each
/// of its contact points.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct SlotMotion {
    /// The environment's acceleration at step start.
    acceleration: DVec3,
    velocity: DVec3,
    angular_velocity: DVec3,
}

impl SlotMotion {
    /// Into `motions`, slot by slot: the fixed slot, then the `awake` bodies in slot order.
    pub(super) fn gather(
        motions: &mut Vec<SlotMotion>,
        bodies: &[RigidBody],
        awake: &[u32],
        forces: &[EnvironmentForce],
    ) {
        motions.clear();
        // The fixed slot: nothing that does not move accelerates (its velocities are not read).
        motions.push(SlotMotion::default());
        motions.extend((awake.iter()).map(|&i| SlotMotion::of(&bodies[i as usize], forces)));
    }

    fn of(body: &RigidBody, forces: &[EnvironmentForce]) -> Self {
        SlotMotion {
            acceleration: environment_acceleration(body, forces),
            velocity: body.velocity(),
            angular_velocity: body.angular_velocity(),
        }
    }
}

/// Zero for a body no force moves: asleep, or kinematic (whose infinite mass would make
/// gravity's force infinite).
fn environment_acceleration(body: &RigidBody, forces: &[EnvironmentForce]) -> DVec3 {
    if !(body.is_awake() && body.is_dynamic()) {
        return DVec3::ZERO;
    }
    forces.iter().map(|f| f.force_on(body)).sum::<DVec3>() * body.inv_mass
}

/// Velocity at step start of the material point at `lever` from the body's centre of mass
/// (the passes take theirs from the momenta: `PointConstraint::speeds`).
#[inline(always)]
fn velocity_at_start(body: &RigidBody, slot: u32, motions: &[SlotMotion], lever: DVec3) -> DVec3 {
    if moves(slot) {
        let motion = &motions[slot as usize];
        motion.velocity + motion.angular_velocity.cross(lever)
    } else {
        body.velocity() + body.angular_velocity().cross(lever)
    }
}

/// The constraint of one contact point, whose normal has the tangents `[t1, t2]`, its
/// anchors and what restitution reads of it.
#[inline(always)]
pub(super) fn prepare<L: Lanes>(
    l: L,
    bodies: &[RigidBody],
    slots: &SolverBodies,
    contact: &ContactInput,
    [t1, t2]: [DVec3; 2],
    motions: &[SlotMotion],
    dt: f64,
) -> (PointConstraint, PointAnchors, PointImpact) {
    let (a, b) = (&bodies[contact.a], &bodies[contact.b]);
    // The passes read the directions and levers as f32 (`PointConstraint`): everything here
    // is worked out from those same values, so that the passes solve the constraint prepared.
    let normal = rounded_to_f32(contact.normal);
    let directions = [normal, rounded_to_f32(t1), rounded_to_f32(t2)];
    let [r_a, r_b] = contact.levers.map(rounded_to_f32);
    let (slot_a, slot_b) = (slots.slot_of(contact.a), slots.slot_of(contact.b));
    let relative_velocity =
        velocity_at_start(b, slot_b, motions, r_b) - velocity_at_start(a, slot_a, motions, r_a);
    let approach_speed = normal.dot(relative_velocity);
    let acceleration = |slot: u32| motions[slot as usize].acceleration;
    let approach_acceleration = normal.dot(acceleration(slot_b) - acceleration(slot_a));
    let across = F64x4::transpose(directions);
    let side_a = SideGeometry::new(l, a, slot_a, r_a, &across);
    let side_b = SideGeometry::new(l, b, slot_b, r_b, &across);
    let separation_offset = contact.separation
        - normal.dot(r_b - r_a + b.position - a.position)
        - normal.dot(side_b.anchor_shift - side_a.anchor_shift);
    let (anchor_a, anchor_b) = (
        side_a.anchor_at(slot_a, a.position, a.orientation),
        side_b.anchor_at(slot_b, b.position, b.orientation),
    );
    let inv_masses = inv_mass(a, slot_a) + inv_mass(b, slot_b);
    let [normal_mass, tangent_1, tangent_2] = effective_masses(l, &side_a, &side_b, inv_masses);
    let anchors = PointAnchors {
        a: side_a.anchor,
        b: side_b.anchor,
        separation_offset,
    };
    let [coupling_1, coupling_2] = normal_to_tangent(l, &side_a, &side_b, inv_masses, &across);
    let constraint = PointConstraint {
        pairs_with_next: false,
        deep: false,
        separation: normal.dot(anchor_b - anchor_a) + separation_offset,
        normal_to_tangent: [coupling_1 as f32, coupling_2 as f32],
        a: side_a.into_lanes(),
        b: side_b.into_lanes(),
        across: F32x4::narrowed3(across),
        slots: [slot_a, slot_b],
        normal_mass,
        tangent_mass: [tangent_1 as f32, tangent_2 as f32],
        impulse: contact.warm_impulse,
        max_normal_impulse: 0.0,
        friction: (a.material.friction * b.material.friction).sqrt() as f32,
    };
    let impact = PointImpact {
        approach_speed,
        fastest_approach: fastest_approach(approach_speed, approach_acceleration, contact, dt),
        approach_acceleration,
        restitution: a.material.restitution.min(b.material.restitution),
    };
    (constraint, anchors, impact)
}

/// The mass an impulse along each direction meets: the inverse of the report's denominator
/// 1/mA + 1/mB + (rA × d)·IA⁻¹(rA × d) + (rB × d)·IB⁻¹(rB × d), from the arms and spins the
/// sides hold (`inv_masses` is 1/mA + 1/mB). A body that does not move in this step counts
/// as immovable, as the impulses treat it.
#[inline(always)]
fn effective_masses<L: Lanes>(
    l: L,
    a: &SideGeometry<L::Vector>,
    b: &SideGeometry<L::Vector>,
    inv_masses: f64,
) -> [f64; 3] {
    let inverse = (l.load(F64x4::splat(inv_masses)) + a.arm_dot_spin() + b.arm_dot_spin()).store();
    let mass = |k: usize| {
        let inverse = inverse.lane(k);
        if inverse > 0.0 { 1.0 / inverse } else { 0.0 }
    };
    [mass(0), mass(1), mass(2)]
}

/// `PointConstraint::normal_to_tangent`: the relative speed along each tangent that a unit
/// normal impulse adds.
#[inline(always)]
fn normal_to_tangent<L: Lanes>(
    l: L,
    a: &SideGeometry<L::Vector>,
    b: &SideGeometry<L::Vector>,
    inv_masses: f64,
    across: &[F64x4; 3],
) -> [f64; 2] {
    // d_k · n for each direction k, then the arms' share.
    let n = [across[0].lane(0), across[1].lane(0), across[2].lane(0)];
    let [x, y, z] = load3(l, across);
    let along_normal = x * n[0] + y * n[1] + z * n[2];
    let coupling =
        (along_normal * inv_masses + a.normal_arm_dot_spin() + b.normal_arm_dot_spin()).store();
    [coupling.lane(1), coupling.lane(2)]
}

/// The fastest the pair can be closing when it meets in this step with no other contact
/// pushing it: falling the whole gap from its speed at step start under the environment's
/// acceleration |a|, −√(v² + 2|a|s), plus |a|·dt of slack for the discrete arc's offsets.
#[inline(always)]
fn fastest_approach(speed: f64, acceleration: f64, contact: &ContactInput, dt: f64) -> f64 {
    let closing = speed.min(0.0);
    let gap = contact.separation.max(0.0);
    let fall = (closing * closing + 2.0 * acceleration.abs() * gap).sqrt();
    -fall - acceleration.abs() * dt
}

/// Sets `pairs_with_next` on the contact before contact `k` in pass order: whether the two
/// may be solved side by side.
#[inline(always)]
pub(super) fn pair_with_previous(constraints: &mut [PointConstraint], k: usize) {
    if let Some(previous) = k.checked_sub(1) {
        constraints[previous].pairs_with_next =
            independent(&constraints[previous], &constraints[k]);
    }
}

/// Whether two contacts share no moving body, so that either may be solved first.
#[inline(always)]
fn independent(x: &PointConstraint, y: &PointConstraint) -> bool {
    x.slots
        .iter()
        .all(|&slot| !moves(slot) || !y.slots.contains(&slot))
}
