//! The joints' share of a soft step (`solver::soft`): **prepare** (each joint's bodies'
//! solver slots and inverse masses), the first **warm start** (the impulses the joint
//! ended the last step with), the **biased** and **relax** passes of each substep (the
//! relax pass also holds the next substep's warm start), and
//! **finish** (impulses kept for the next step, the reaction measured).
//!
//! The joints are solved serially, in the order they were added, before the contacts'
//! colours in each pass: the result stays deterministic with any number of threads, and
//! the contacts see bodies the joints have already held together.
//!
//! A joint's warm start is its impulses along its directions at the poses where the bodies
//! start the substep. Those are the poses where the last relax pass left them, so that pass
//! computes it and holds it in the bodies' slots (`SolverBody::joints_warm_start`), which
//! apply it as the next substep starts: no pass of its own. The contacts' warm start is
//! carried per body differently (the change in momenta over a substep,
//! `SolverBodies::store_warm_start`), which suits directions fixed for the step; a joint's
//! turn with its bodies (a pendulum's rod), and carried that way its impulse of the last
//! substep would keep its old direction and push the bob along its path, so the joints take
//! what they give out of that change as they give it (`Side::write`).

use glam::{DMat3, DQuat, DVec3};

use super::ball::{self, solve_ball};
use super::desc::JointKind;
use super::joint::{Joint, JointImpulses, rotation_of};
use super::rows::{
    BodyView, Bound, LinearRow, RowPass, point_mass, solve_angular, solve_axial, solve_point,
};
use crate::physics::dynamics::body::RigidBody;
#[cfg(target_arch = "x86_64")]
use crate::physics::solver::lanes::Avx2;
use crate::physics::solver::lanes::{F64x4, Lanes, Portable};
use crate::physics::solver::soft::Softness;
use crate::physics::solver::solver_bodies::{FIXED_SLOT, SolverBodies, SolverBody};

/// A joint prepared for one step. A pass streams these through memory, so the record holds
/// only what the rows read, the sides first and then the joint (whose fields a ball joint
/// reads come first: `Joint`), so that a ball joint's pass touches the record's first few
/// cache lines (BENCHMARKS.md, "Compact joint records").
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub(crate) struct JointConstraint {
    pub(super) sides: [Side; 2],
    /// The inverse of the mass the anchors' point block meets (`rows::point_mass`), with
    /// the levers and inertias at step start (zero for the kinds without the block).
    pub(super) point_mass: DMat3,
    pub(super) joint: Joint,
    /// Its place in the world's joint list.
    index: usize,
}

/// One body of a prepared joint.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub(super) struct Side {
    pub(super) slot: u32,
    /// The body's index in the world: where the pose of a body without a moving slot is
    /// read (it does not change during the step).
    pub(super) body: u32,
    /// 1/m as impulses see it: zero unless the body is dynamic and awake.
    pub(super) inv_mass: f64,
    /// I⁻¹ in world axes at step start, as impulses see it.
    pub(super) inv_inertia: DMat3,
}

impl Side {
    fn new(body: &RigidBody, index: usize, slot: u32) -> Side {
        let moves = slot != FIXED_SLOT && body.is_dynamic();
        let inv_mass = if moves { body.inv_mass } else { 0.0 };
        let inv_inertia = if moves {
            body.inv_inertia_world
        } else {
            DMat3::ZERO
        };
        Side {
            slot,
            body: index as u32,
            inv_mass,
            inv_inertia,
        }
    }

    #[inline(always)]
    fn view(&self, slots: &[SolverBody], bodies: &[RigidBody]) -> BodyView {
        let (position, orientation, velocity, spin) = if self.slot == FIXED_SLOT {
            let body = &bodies[self.body as usize];
            (body.position, body.orientation, DVec3::ZERO, DVec3::ZERO)
        } else {
            let slot = &slots[self.slot as usize];
            let [x, y, z] = slot.orientation.map(|c| c.to_vec3());
            let momentum = slot.angular_momentum.to_vec3();
            // A kinematic body's slot holds its spin scaled as its velocity (`SolverBodies`).
            let spin = if self.inv_mass != 0.0 {
                self.inv_inertia * momentum
            } else {
                momentum * slot.inv_mass
            };
            (
                slot.position.to_vec3(),
                DMat3::from_cols(x, y, z),
                slot.linear_momentum.to_vec3() * slot.inv_mass,
                spin,
            )
        };
        BodyView {
            position,
            orientation,
            velocity,
            spin,
            inv_mass: self.inv_mass,
            inv_inertia: self.inv_inertia,
            linear_impulse: DVec3::ZERO,
            angular_impulse: DVec3::ZERO,
        }
    }

    /// Adds `impulse` to the slot's joints' warm start (a body that impulses do not move is
    /// never written).
    #[inline(always)]
    fn hold(&self, impulse: Impulse, slots: &mut [SolverBody]) {
        if self.inv_mass == 0.0 {
            return;
        }
        let held = &mut slots[self.slot as usize].joints_warm_start;
        add_to_lanes(held, [impulse.linear, impulse.angular]);
    }

    /// Adds the momenta the rows gave the body to its slot, and counts them as given before
    /// the contacts, so that the body carries only the contacts' share to the next
    /// substep's warm start (see the module comment). A body that impulses do not move
    /// (static, asleep, kinematic) is never written.
    #[inline(always)]
    fn write(&self, view: &BodyView, slots: &mut [SolverBody]) {
        if self.inv_mass == 0.0 {
            return;
        }
        let slot = &mut slots[self.slot as usize];
        let impulses = [view.linear_impulse, view.angular_impulse];
        add_to_lanes(
            [&mut slot.linear_momentum, &mut slot.angular_momentum],
            impulses,
        );
        add_to_lanes(&mut slot.before_contacts, impulses);
    }
}

/// Adds a linear and an angular impulse to a slot's pair of lanes (momenta, or what is held
/// for a warm start).
#[inline(always)]
fn add_to_lanes<'a>(
    totals: impl IntoIterator<Item = &'a mut F64x4>,
    [linear, angular]: [DVec3; 2],
) {
    for (total, impulse) in totals.into_iter().zip([linear, angular]) {
        *total = F64x4::from_vec3(total.to_vec3() + impulse);
    }
}

/// Prepares every joint with a body that moves in this step, in joint order. `slots` must
/// already be assigned to this step's awake bodies.
pub(crate) fn prepare(
    prepared: &mut Vec<JointConstraint>,
    joints: &[Option<Joint>],
    bodies: &[RigidBody],
    slots: &SolverBodies,
) {
    prepared.clear();
    for (index, joint) in joints.iter().enumerate() {
        let Some(joint) = joint else { continue };
        let (a, b) = (joint.body_a.index(), joint.body_b.index());
        if !(bodies[a].motion.takes_part() && bodies[b].motion.takes_part()) {
            continue;
        }
        let sides = [
            Side::new(&bodies[a], a, slots.slot_of(a)),
            Side::new(&bodies[b], b, slots.slot_of(b)),
        ];
        if sides.iter().all(|s| s.inv_mass == 0.0) {
            continue;
        }
        prepared.push(JointConstraint {
            index,
            joint: *joint,
            point_mass: point_mass_at_start(joint, &sides, [&bodies[a], &bodies[b]]),
            sides,
        });
    }
}

/// The inverse mass of the joint's point block, for the kinds that have one, with the
/// levers at the bodies' poses at step start: recomputed at every pass it cost more than
/// the rest of a ball joint's row, and the inertias it takes are those of step start
/// anyway (BENCHMARKS.md, "Joint point mass once per step").
fn point_mass_at_start(joint: &Joint, sides: &[Side; 2], bodies: [&RigidBody; 2]) -> DMat3 {
    match joint.kind {
        JointKind::Ball | JointKind::Fixed | JointKind::Hinge | JointKind::ConeTwist => {
            let [a, b] = sides;
            let ra = bodies[0].orientation * joint.local_anchor_a;
            let rb = bodies[1].orientation * joint.local_anchor_b;
            let inverse = point_mass(
                [ra, rb],
                [a.inv_mass, b.inv_mass],
                [&a.inv_inertia, &b.inv_inertia],
            );
            inverse.unwrap_or(DMat3::ZERO)
        }
        JointKind::Slider | JointKind::Distance => DMat3::ZERO,
    }
}

/// The first substep's warm start: each joint's impulses of the last step, along its
/// directions at step start, held in the slots until the substep starts.
pub(crate) fn hold_first_warm_start(
    prepared: &[JointConstraint],
    slots: &mut [SolverBody],
    bodies: &[RigidBody],
) {
    for c in prepared {
        if c.joint.kind == JointKind::Ball {
            ball::hold_warm_start(Portable, c, slots, bodies);
        } else {
            hold_general(c, slots, bodies);
        }
    }
}

/// One joint's first warm start through the general path (`BodyView`s).
pub(super) fn hold_general(c: &JointConstraint, slots: &mut [SolverBody], bodies: &[RigidBody]) {
    let (a, b) = c.views(slots, bodies);
    let g = Geometry::of(&c.joint, &a, &b);
    c.hold_warm_start(&g, &a, &b, slots);
}

/// Whether a relax pass also holds the next substep's warm start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum NextSubstep {
    WarmStart,
    None,
}

/// One pass over the joints, in order (see the module comment); a relax pass followed by a
/// substep then holds that substep's warm start.
pub(crate) fn solve_all(
    prepared: &mut [JointConstraint],
    slots: &mut [SolverBody],
    bodies: &[RigidBody],
    pass: RowPass,
    next: NextSubstep,
) {
    #[cfg(target_arch = "x86_64")]
    if let Some(avx) = Avx2::detect() {
        // SAFETY: the processor has AVX2, as `avx` proves.
        return unsafe { solve_all_avx2(avx, prepared, slots, bodies, pass, next) };
    }
    solve_all_inline(Portable, prepared, slots, bodies, pass, next);
}

/// `solve_all` compiled with AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn solve_all_avx2(
    avx: Avx2,
    prepared: &mut [JointConstraint],
    slots: &mut [SolverBody],
    bodies: &[RigidBody],
    pass: RowPass,
    next: NextSubstep,
) {
    solve_all_inline(avx, prepared, slots, bodies, pass, next);
}

/// The body of `solve_all`, compiled into each of its variants.
#[inline(always)]
fn solve_all_inline<L: Lanes>(
    l: L,
    prepared: &mut [JointConstraint],
    slots: &mut [SolverBody],
    bodies: &[RigidBody],
    pass: RowPass,
    next: NextSubstep,
) {
    for c in prepared.iter_mut() {
        if c.joint.kind == JointKind::Ball {
            solve_ball(l, c, slots, bodies, pass, next);
        } else {
            solve_general(c, slots, bodies, pass, next);
        }
    }
}

/// One joint's pass through the general rows (`rows`) on two `BodyView`s.
#[inline(always)]
pub(super) fn solve_general(
    c: &mut JointConstraint,
    slots: &mut [SolverBody],
    bodies: &[RigidBody],
    pass: RowPass,
    next: NextSubstep,
) {
    let (mut a, mut b) = c.views(slots, bodies);
    let g = solve_joint(&mut c.joint, &c.point_mass, [&mut a, &mut b], pass);
    c.write(&a, &b, slots);
    if next == NextSubstep::WarmStart {
        // The rows moved no pose: the levers they worked with are still the bodies'.
        c.hold_warm_start(&g, &a, &b, slots);
    }
}

impl JointConstraint {
    /// Holds the impulses the joint holds, along its directions at the views' poses (where
    /// it acts: `g`), in its bodies' slots for the next warm start.
    #[inline(always)]
    fn hold_warm_start(&self, g: &Geometry, a: &BodyView, b: &BodyView, slots: &mut [SolverBody]) {
        let [on_a, on_b] = held_impulses(&self.joint, g, a, b);
        self.sides[0].hold(on_a, slots);
        self.sides[1].hold(on_b, slots);
    }

    /// Both bodies as the rows see them now (the sides read in place: copied out whole, as
    /// an array `map` does, they went through a call to `memcpy` per joint).
    #[inline(always)]
    fn views(&self, slots: &[SolverBody], bodies: &[RigidBody]) -> (BodyView, BodyView) {
        let [a, b] = &self.sides;
        (a.view(slots, bodies), b.view(slots, bodies))
    }

    #[inline(always)]
    fn write(&self, a: &BodyView, b: &BodyView, slots: &mut [SolverBody]) {
        self.sides[0].write(a, slots);
        self.sides[1].write(b, slots);
    }
}

/// Hands each joint its impulses for the next step's warm start, and its reaction: the
/// force and torque (about b's anchor) it put on b, from the impulses per substep of
/// length `h`.
pub(crate) fn finish(
    prepared: &[JointConstraint],
    slots: &[SolverBody],
    bodies: &[RigidBody],
    joints: &mut [Option<Joint>],
    h: f64,
) {
    for c in prepared {
        let [linear, angular, rb] = if c.joint.kind == JointKind::Ball {
            ball::impulse_on_b(Portable, c, slots, bodies)
        } else {
            impulse_on_b_general(c, slots, bodies)
        };
        let Some(joint) = joints[c.index].as_mut() else {
            continue;
        };
        joint.impulses = c.joint.impulses;
        joint.angle = c.joint.angle;
        joint.reaction_force = linear / h;
        joint.reaction_torque = (angular - rb.cross(linear)) / h;
    }
}

/// The linear and angular impulse the joint's impulses put on b at the bodies' current
/// poses, and b's lever, through the general path (`BodyView`s).
pub(super) fn impulse_on_b_general(
    c: &JointConstraint,
    slots: &[SolverBody],
    bodies: &[RigidBody],
) -> [DVec3; 3] {
    let (a, b) = c.views(slots, bodies);
    let g = Geometry::of(&c.joint, &a, &b);
    let [_, on_b] = held_impulses(&c.joint, &g, &a, &b);
    [on_b.linear, on_b.angular, g.rb]
}

/// Where a joint's rows act in the bodies' current poses.
struct Geometry {
    ra: DVec3,
    rb: DVec3,
}

impl Geometry {
    #[inline(always)]
    fn of(joint: &Joint, a: &BodyView, b: &BodyView) -> Geometry {
        Geometry {
            ra: a.orientation * joint.local_anchor_a,
            rb: b.orientation * joint.local_anchor_b,
        }
    }

    /// The joint's axis as a carries it (hinge, slider): not read by the other kinds, whose
    /// passes then skip that part of the record.
    fn axis(joint: &Joint, a: &BodyView) -> DVec3 {
        a.orientation * joint.local_axis_a
    }

    /// From a's anchor to b's.
    fn separation(&self, a: &BodyView, b: &BodyView) -> DVec3 {
        (b.position + self.rb) - (a.position + self.ra)
    }
}

/// Every row of one joint, once, in the order the kind needs: what a joint allows (motor,
/// limits, spring) first, what it forbids last, so that the hard rows have the last word.
#[inline(always)]
fn solve_joint(
    joint: &mut Joint,
    point_mass: &DMat3,
    [a, b]: [&mut BodyView; 2],
    pass: RowPass,
) -> Geometry {
    let g = Geometry::of(joint, a, b);
    let mut held = joint.impulses;
    let impulses = &mut held;
    match joint.kind {
        JointKind::Ball => solve_point([a, b], [g.ra, g.rb], point_mass, &mut impulses.point, pass),
        JointKind::Fixed => {
            let error = rotation_error(joint, a, b);
            solve_angular([a, b], DVec3::ZERO, error, &mut impulses.angular, pass);
            solve_point([a, b], [g.ra, g.rb], point_mass, &mut impulses.point, pass);
        }
        JointKind::Hinge => {
            joint.angle = hinge_angle(joint, a, b);
            let axis = Geometry::axis(joint, a);
            let drives = Drives::of(joint, pass, || hinge_turning(axis, [a, b], [g.ra, g.rb]));
            axial_rows([a, b], axis, joint.angle, drives, impulses, pass);
            let error = axis.cross(b.orientation * joint.local_axis_b);
            solve_angular([a, b], axis, error, &mut impulses.angular, pass);
            solve_point([a, b], [g.ra, g.rb], point_mass, &mut impulses.point, pass);
        }
        JointKind::Slider => solve_slider(joint, impulses, &g, [a, b], pass),
        JointKind::Distance => solve_distance(joint, impulses, &g, [a, b], pass),
        JointKind::ConeTwist => {
            let cone = ConeGeometry::of(joint, a, b);
            joint.angle = cone.twist;
            solve_cone_twist(joint, &cone, [a, b], impulses, pass);
            solve_point([a, b], [g.ra, g.rb], point_mass, &mut impulses.point, pass);
        }
    }
    joint.impulses = held;
    g
}

/// A cone-twist joint's angles in the bodies' current poses.
struct ConeGeometry {
    /// The angle between a's axis and b's, rad in [0, π].
    swing: f64,
    /// The direction about which b's axis has swung away from a's (zero when they are
    /// aligned or opposite, where it is undefined).
    swing_axis: DVec3,
    /// The axis halfway between the two, about which the twist is measured and limited.
    twist_axis: DVec3,
    /// b's turn about its axis relative to a's once the swing is taken out, counted through
    /// whole turns from `Joint::angle`.
    twist: f64,
}

impl ConeGeometry {
    fn of(joint: &Joint, a: &BodyView, b: &BodyView) -> ConeGeometry {
        let axis_a = a.orientation * joint.local_axis_a;
        let axis_b = b.orientation * joint.local_axis_b;
        let across = axis_a.cross(axis_b);
        let swing = across.length().atan2(axis_a.dot(axis_b));
        // a's reference carried along the shortest turn from a's axis to b's.
        let swung =
            DQuat::from_rotation_arc(axis_a, axis_b) * (a.orientation * joint.local_reference_a);
        let ref_b = b.orientation * joint.local_reference_b;
        let measured = axis_b.dot(swung.cross(ref_b)).atan2(swung.dot(ref_b));
        ConeGeometry {
            swing,
            swing_axis: across.normalize_or_zero(),
            twist_axis: (axis_a + axis_b).normalize_or(axis_b),
            twist: continued(joint.angle, measured),
        }
    }
}

/// The cone's row (its impulse held in `along`), then the twist limits as a hinge's
/// (`lower`, `upper`; a cone-twist takes no motor or servo).
fn solve_cone_twist(
    joint: &Joint,
    cone: &ConeGeometry,
    [a, b]: [&mut BodyView; 2],
    impulses: &mut JointImpulses,
    pass: RowPass,
) {
    if cone.swing_axis != DVec3::ZERO {
        let room = joint.cone - cone.swing;
        let back = -cone.swing_axis;
        solve_axial(
            [a, b],
            back,
            room,
            Bound::AtLeast,
            &mut impulses.along,
            pass,
        );
    }
    let drives = Drives::of(joint, pass, || 1.0);
    axial_rows([a, b], cone.twist_axis, cone.twist, drives, impulses, pass);
}

/// What drives a hinge or slider along its axis in one pass: its motor's and servo's rows
/// (the servo's with its target as C = 0), and its limits.
struct Drives {
    motor: Option<Bound>,
    servo: Option<(Bound, f64)>,
    limits: Option<(f64, f64)>,
}

impl Drives {
    /// `turning`: how many times the inertia the servo's row meets the bodies turn with
    /// (`hinge_turning`; 1 along a slider), asked only of a joint with a servo.
    fn of(joint: &Joint, pass: RowPass, turning: impl FnOnce() -> f64) -> Drives {
        let motor = joint.motor.map(|m| Bound::Motor {
            speed: m.speed,
            limit: m.max_force * pass.h,
        });
        let servo = joint.servo.filter(|s| s.hertz > 0.0).map(|s| {
            // The row's spring is its own mass times ω², its damper 2ζ times its mass times
            // ω: both scaled by √turning, the spring is the user's frequency and damping
            // ratio on the inertia the bodies really turn with.
            let scale = turning().sqrt();
            let softness = Softness::new(s.hertz * scale, s.damping_ratio * scale, pass.h);
            let limit = s.max_force * pass.h;
            (Bound::Servo { softness, limit }, s.target)
        });
        Drives {
            motor,
            servo,
            limits: joint.limits,
        }
    }
}

/// How many times the inertia the bodies turn with about a hinge exceeds what its angular
/// row meets, the bodies' inertias about their centres (at least 1). A body turning about
/// a hinge off its centre swings its mass around too: m d² more, with d the distance from
/// the axis to its centre (a door on its edge: 4 times its own), the hinge's point rows
/// holding it. Each body is taken as turning about the hinge with the other held, exact
/// when one of them does not move.
fn hinge_turning(axis: DVec3, [a, b]: [&BodyView; 2], levers: [DVec3; 2]) -> f64 {
    let about_centres = |body: &BodyView| axis.dot(body.inv_inertia * axis);
    let about_hinge = |body: &BodyView, lever: DVec3| {
        // 1 / (I + m d²) from 1/I and 1/m: zero for a body that does not turn.
        let (inv_inertia, inv_mass) = (about_centres(body), body.inv_mass);
        let d2 = lever.cross(axis).length_squared();
        let denominator = inv_mass + inv_inertia * d2;
        if denominator > 0.0 {
            inv_inertia * inv_mass / denominator
        } else {
            inv_inertia
        }
    };
    let row = about_centres(a) + about_centres(b);
    let hinge = about_hinge(a, levers[0]) + about_hinge(b, levers[1]);
    if hinge > 0.0 {
        (row / hinge).max(1.0)
    } else {
        1.0
    }
}

/// A hinge's motor, servo and limits about `axis`, at the hinge `angle` (and a cone-twist's
/// twist limits).
fn axial_rows(
    [a, b]: [&mut BodyView; 2],
    axis: DVec3,
    angle: f64,
    drives: Drives,
    impulses: &mut JointImpulses,
    pass: RowPass,
) {
    if let Some(bound) = drives.motor {
        solve_axial([a, b], axis, 0.0, bound, &mut impulses.motor, pass);
    }
    if let Some((bound, target)) = drives.servo {
        solve_axial(
            [a, b],
            axis,
            angle - target,
            bound,
            &mut impulses.servo,
            pass,
        );
    }
    if let Some((lo, hi)) = drives.limits {
        let lower = angle - lo;
        solve_axial(
            [a, b],
            axis,
            lower,
            Bound::AtLeast,
            &mut impulses.lower,
            pass,
        );
        let upper = hi - angle;
        solve_axial(
            [a, b],
            -axis,
            upper,
            Bound::AtLeast,
            &mut impulses.upper,
            pass,
        );
    }
}

/// No turn, and b's anchor on the line through a's along the axis; the motor and limits
/// act along it.
fn solve_slider(
    joint: &Joint,
    impulses: &mut JointImpulses,
    g: &Geometry,
    [a, b]: [&mut BodyView; 2],
    pass: RowPass,
) {
    let d = g.separation(a, b);
    let axis = Geometry::axis(joint, a);
    let offset = axis.dot(d);
    let along = LinearRow {
        n: axis,
        ra: g.ra + d,
        rb: g.rb,
    };
    let drives = Drives::of(joint, pass, || 1.0);
    if let Some(bound) = drives.motor {
        along.solve([a, b], 0.0, bound, &mut impulses.motor, pass);
    }
    if let Some((bound, target)) = drives.servo {
        along.solve([a, b], offset - target, bound, &mut impulses.servo, pass);
    }
    if let Some((lo, hi)) = drives.limits {
        solve_linear_limits(along, [a, b], offset, [Some(lo), Some(hi)], impulses, pass);
    }
    let error = rotation_error(joint, a, b);
    solve_angular([a, b], DVec3::ZERO, error, &mut impulses.angular, pass);
    let (t1, t2) = axis.any_orthonormal_pair();
    for (k, n) in [t1, t2].into_iter().enumerate() {
        let d = g.separation(a, b);
        let row = LinearRow { n, ..along };
        row.solve(
            [a, b],
            n.dot(d),
            Bound::Equal,
            &mut impulses.across[k],
            pass,
        );
    }
}

/// The anchors at the joint's length (a rod), within its limits (a rope), or pulled by
/// its spring.
fn solve_distance(
    joint: &Joint,
    impulses: &mut JointImpulses,
    g: &Geometry,
    [a, b]: [&mut BodyView; 2],
    pass: RowPass,
) {
    let d = g.separation(a, b);
    let length = d.length();
    if length < 1e-12 {
        return; // no direction to push along
    }
    let row = LinearRow {
        n: d / length,
        ra: g.ra,
        rb: g.rb,
    };
    let limits = joint.limits.unwrap_or((0.0, f64::INFINITY));
    if limits.0 == limits.1 {
        row.solve(
            [a, b],
            length - limits.0,
            Bound::Equal,
            &mut impulses.along,
            pass,
        );
        return;
    }
    if let Some(spring) = joint.spring.filter(|s| s.hertz > 0.0) {
        let soft = Softness::new(spring.hertz, spring.damping_ratio, pass.h);
        let c = length - joint.length;
        row.solve([a, b], c, Bound::Spring(soft), &mut impulses.along, pass);
    }
    // A rope's lower limit of 0 and an open upper one hold nothing.
    let lower = (limits.0 > 0.0).then_some(limits.0);
    let upper = limits.1.is_finite().then_some(limits.1);
    solve_linear_limits(row, [a, b], length, [lower, upper], impulses, pass);
}

/// The rows that keep `value`, measured along `row`, at or above the lower bound and at or
/// below the upper one (each when given): the slider's offset and the rope's length.
fn solve_linear_limits(
    row: LinearRow,
    [a, b]: [&mut BodyView; 2],
    value: f64,
    [lower, upper]: [Option<f64>; 2],
    impulses: &mut JointImpulses,
    pass: RowPass,
) {
    if let Some(lo) = lower {
        row.solve(
            [a, b],
            value - lo,
            Bound::AtLeast,
            &mut impulses.lower,
            pass,
        );
    }
    if let Some(hi) = upper {
        let back = LinearRow { n: -row.n, ..row };
        back.solve(
            [a, b],
            hi - value,
            Bound::AtLeast,
            &mut impulses.upper,
            pass,
        );
    }
}

/// The small rotation, world, that b has turned away from its orientation at creation
/// relative to a (twice the vector part of the error quaternion).
fn rotation_error(joint: &Joint, a: &BodyView, b: &BodyView) -> DVec3 {
    let target = rotation_of(a.orientation) * joint.relative_rotation;
    let mut error = rotation_of(b.orientation) * target.inverse();
    if error.w < 0.0 {
        error = -error;
    }
    2.0 * DVec3::new(error.x, error.y, error.z)
}

/// The hinge's angle, rad: b's turn about the axis since creation, the turn measured in
/// (−π, π] carried on from `Joint::angle` through whole turns. A pass turns a hinge by far
/// less than half a turn (that would take 1 500 rad/s at 8 substeps of 1/60 s).
fn hinge_angle(joint: &Joint, a: &BodyView, b: &BodyView) -> f64 {
    let axis = a.orientation * joint.local_axis_a;
    let ref_a = a.orientation * joint.local_reference_a;
    let ref_b = b.orientation * joint.local_reference_b;
    let measured = axis.dot(ref_a.cross(ref_b)).atan2(ref_a.dot(ref_b));
    continued(joint.angle, measured)
}

/// The angle `measured` in (−π, π], carried on from `last` through whole turns: the one of
/// its values a whole number of turns apart that lies within half a turn of `last`.
fn continued(last: f64, measured: f64) -> f64 {
    let step = measured - last;
    let turns = (step / std::f64::consts::TAU).round();
    last + step - turns * std::f64::consts::TAU
}

/// The linear and angular impulse on a and on b of the impulses the joint holds, along its
/// directions at the views' poses (a warm start; a reaction).
#[inline(always)]
fn held_impulses(joint: &Joint, g: &Geometry, a: &BodyView, b: &BodyView) -> [Impulse; 2] {
    let i = &joint.impulses;
    let mut on_a = Impulse::at(g.ra, -i.point).turned(-i.angular);
    let mut on_b = Impulse::at(g.rb, i.point).turned(i.angular);
    let (n, ra) = match joint.kind {
        JointKind::Ball | JointKind::Fixed => return [on_a, on_b],
        JointKind::Hinge => {
            let axial = Geometry::axis(joint, a) * (i.motor + i.servo + i.lower - i.upper);
            return [on_a.turned(-axial), on_b.turned(axial)];
        }
        JointKind::ConeTwist => {
            let cone = ConeGeometry::of(joint, a, b);
            let turn = -cone.swing_axis * i.along + cone.twist_axis * (i.lower - i.upper);
            return [on_a.turned(-turn), on_b.turned(turn)];
        }
        JointKind::Slider => {
            let axis = Geometry::axis(joint, a);
            let (t1, t2) = axis.any_orthonormal_pair();
            let across = t1 * i.across[0] + t2 * i.across[1];
            let along = axis * (i.motor + i.servo + i.lower - i.upper);
            (along + across, g.ra + g.separation(a, b))
        }
        JointKind::Distance => {
            let n = g.separation(a, b).normalize_or_zero();
            (n * (i.along + i.lower - i.upper), g.ra)
        }
    };
    on_a.add(Impulse::at(ra, -n));
    on_b.add(Impulse::at(g.rb, n));
    [on_a, on_b]
}

/// A linear impulse and an angular one, about the centre of mass.
#[derive(Clone, Copy, Debug)]
struct Impulse {
    linear: DVec3,
    angular: DVec3,
}

impl Impulse {
    /// A linear impulse at the lever `r`.
    #[inline(always)]
    fn at(r: DVec3, linear: DVec3) -> Impulse {
        Impulse {
            linear,
            angular: r.cross(linear),
        }
    }

    #[inline(always)]
    fn turned(self, angular: DVec3) -> Impulse {
        Impulse {
            angular: self.angular + angular,
            ..self
        }
    }

    #[inline(always)]
    fn add(&mut self, other: Impulse) {
        self.linear += other.linear;
        self.angular += other.angular;
    }
}
