//! A ball joint's pass in lanes (see `solver::lanes`): what the general path computes for a
//! ball joint (`solve::solve_joint` on two `BodyView`s, then `write` and the warm start's
//! `hold`), component by component and in the same order, so to the same bits, but with a
//! vector's three components in one register. The general path spent more moving
//! components between registers than computing (BENCHMARKS.md, "Ball joints in lanes").

use glam::{DMat3, DVec3};

use super::solve::{JointConstraint, NextSubstep, Side};
use crate::physics::dynamics::body::RigidBody;
use crate::physics::joints::rows::RowPass;
use crate::physics::solver::lanes::{F64x4, LaneVector, Lanes};
use crate::physics::solver::solver_bodies::{FIXED_SLOT, SolverBody};

/// One body of the joint in lanes: where it is and how it moves now.
struct Body<V> {
    position: V,
    orientation: [V; 3],
    velocity: V,
    spin: V,
}

/// The joint's rows for one pass: the point block, then its impulses written to the bodies'
/// slots and, before another substep, held for its warm start.
#[inline(always)]
pub(super) fn solve_ball<L: Lanes>(
    l: L,
    c: &mut JointConstraint,
    slots: &mut [SolverBody],
    bodies: &[RigidBody],
    pass: RowPass,
    next: NextSubstep,
) {
    let [side_a, side_b] = &c.sides;
    let (a, b) = (
        body(l, side_a, slots, bodies),
        body(l, side_b, slots, bodies),
    );
    let ra = times(&a.orientation, c.joint.local_anchor_a);
    let rb = times(&b.orientation, c.joint.local_anchor_b);
    let error = (b.position + rb) - (a.position + ra);
    let speed = (b.velocity + b.spin.cross(rb)) - (a.velocity + a.spin.cross(ra));
    let (bias, mass_scale, impulse_scale) = match pass.softness {
        Some(s) => (error * s.bias_rate(), s.mass_scale(), s.impulse_scale()),
        None => (l.load(F64x4::ZERO), 1.0, 0.0),
    };
    let rigid = times_matrix(l, &c.point_mass, speed + bias);
    let accumulated = load3(l, c.joint.impulses.point);
    let impulse = -rigid * mass_scale - accumulated * impulse_scale;
    let point = accumulated + impulse;
    c.joint.impulses.point = point.store().to_vec3();
    // Added to zero as the general path gathers them (which makes a −0 a +0): the same bits.
    let zero = l.load(F64x4::ZERO);
    let on_a = [zero + -impulse, zero + ra.cross(-impulse)];
    let on_b = [zero + impulse, zero + rb.cross(impulse)];
    write(l, side_a, on_a, slots);
    write(l, side_b, on_b, slots);
    if next == NextSubstep::WarmStart {
        hold_impulses(l, c, [ra, rb], point, slots);
    }
}

/// The joint's impulses held in its bodies' slots for the next warm start, with the levers
/// at the bodies' current poses (the first warm start of a step: `solve::hold_first_warm_start`).
#[inline(always)]
pub(super) fn hold_warm_start<L: Lanes>(
    l: L,
    c: &JointConstraint,
    slots: &mut [SolverBody],
    bodies: &[RigidBody],
) {
    let levers = levers(l, c, slots, bodies);
    let point = load3(l, c.joint.impulses.point);
    hold_impulses(l, c, levers, point, slots);
}

/// The linear and angular impulse the joint's impulses put on b, with the levers at the
/// bodies' current poses, and b's lever (`solve::finish`).
#[inline(always)]
pub(super) fn impulse_on_b<L: Lanes>(
    l: L,
    c: &JointConstraint,
    slots: &[SolverBody],
    bodies: &[RigidBody],
) -> [DVec3; 3] {
    let [_, rb] = levers(l, c, slots, bodies);
    let point = load3(l, c.joint.impulses.point);
    let angular = rb.cross(point) + load3(l, c.joint.impulses.angular);
    [point, angular, rb].map(|v| v.store().to_vec3())
}

/// As `held_impulses` for a ball joint, held in the slots: the point impulse `point` at the
/// `levers`, and the angular one (zero for a ball joint, added as the general path adds it).
#[inline(always)]
fn hold_impulses<L: Lanes>(
    l: L,
    c: &JointConstraint,
    [ra, rb]: [L::Vector; 2],
    point: L::Vector,
    slots: &mut [SolverBody],
) {
    let angular = load3(l, c.joint.impulses.angular);
    let [side_a, side_b] = &c.sides;
    hold(l, side_a, [-point, ra.cross(-point) + -angular], slots);
    hold(l, side_b, [point, rb.cross(point) + angular], slots);
}

/// Each body's lever to its anchor at its current pose.
#[inline(always)]
fn levers<L: Lanes>(
    l: L,
    c: &JointConstraint,
    slots: &[SolverBody],
    bodies: &[RigidBody],
) -> [L::Vector; 2] {
    let [side_a, side_b] = &c.sides;
    [
        times(
            &orientation(l, side_a, slots, bodies),
            c.joint.local_anchor_a,
        ),
        times(
            &orientation(l, side_b, slots, bodies),
            c.joint.local_anchor_b,
        ),
    ]
}

/// A body's orientation by columns: from its slot, or from the world for a body without a
/// moving slot.
#[inline(always)]
fn orientation<L: Lanes>(
    l: L,
    side: &Side,
    slots: &[SolverBody],
    bodies: &[RigidBody],
) -> [L::Vector; 3] {
    if side.slot == FIXED_SLOT {
        let o = bodies[side.body as usize].orientation;
        [load3(l, o.x_axis), load3(l, o.y_axis), load3(l, o.z_axis)]
    } else {
        let [x, y, z] = slots[side.slot as usize].orientation;
        [l.load(x), l.load(y), l.load(z)]
    }
}

/// As `Side::view`: a body without a moving slot from the world, at rest.
#[inline(always)]
fn body<L: Lanes>(
    l: L,
    side: &Side,
    slots: &[SolverBody],
    bodies: &[RigidBody],
) -> Body<L::Vector> {
    if side.slot == FIXED_SLOT {
        let zero = l.load(F64x4::ZERO);
        return Body {
            position: load3(l, bodies[side.body as usize].position),
            orientation: orientation(l, side, slots, bodies),
            velocity: zero,
            spin: zero,
        };
    }
    let slot = &slots[side.slot as usize];
    let momentum = l.load(slot.angular_momentum);
    // A kinematic body's slot holds its spin scaled as its velocity (`SolverBodies`).
    let spin = if side.inv_mass != 0.0 {
        times_matrix(l, &side.inv_inertia, momentum)
    } else {
        momentum * slot.inv_mass
    };
    Body {
        position: l.load(slot.position),
        orientation: orientation(l, side, slots, bodies),
        velocity: l.load(slot.linear_momentum) * slot.inv_mass,
        spin,
    }
}

/// As `Side::write`: the momenta the joint gave, added to the slot's momenta and to those
/// it had before the contacts.
#[inline(always)]
fn write<L: Lanes>(l: L, side: &Side, [linear, angular]: [L::Vector; 2], slots: &mut [SolverBody]) {
    if side.inv_mass == 0.0 {
        return;
    }
    let slot = &mut slots[side.slot as usize];
    let momenta = [&mut slot.linear_momentum, &mut slot.angular_momentum];
    add_to_pair(l, momenta, [linear, angular]);
    let [before_linear, before_angular] = &mut slot.before_contacts;
    add_to_pair(l, [before_linear, before_angular], [linear, angular]);
}

/// As `Side::hold`: the joint's impulses added to the slot's next warm start.
#[inline(always)]
fn hold<L: Lanes>(l: L, side: &Side, [linear, angular]: [L::Vector; 2], slots: &mut [SolverBody]) {
    if side.inv_mass == 0.0 {
        return;
    }
    let [held_linear, held_angular] = &mut slots[side.slot as usize].joints_warm_start;
    add_to_pair(l, [held_linear, held_angular], [linear, angular]);
}

/// Adds a linear and an angular impulse to a slot's pair of lanes, as `solve::add_to_lanes`
/// does with plain vectors.
#[inline(always)]
fn add_to_pair<L: Lanes>(l: L, totals: [&mut F64x4; 2], impulses: [L::Vector; 2]) {
    for (total, impulse) in totals.into_iter().zip(impulses) {
        *total = (l.load(*total) + impulse).store();
    }
}

/// A vector into lanes 0 to 2 (lane 3 zero).
#[inline(always)]
fn load3<L: Lanes>(l: L, v: DVec3) -> L::Vector {
    l.load(F64x4::from_vec3(v))
}

/// m v for a matrix by columns in lanes, as glam's `DMat3 * DVec3` sums it.
#[inline(always)]
fn times<V: LaneVector>(columns: &[V; 3], v: DVec3) -> V {
    let [x, y, z] = *columns;
    x * v.x + y * v.y + z * v.z
}

/// m v, v in lanes.
#[inline(always)]
fn times_matrix<L: Lanes>(l: L, m: &DMat3, v: L::Vector) -> L::Vector {
    let columns = [load3(l, m.x_axis), load3(l, m.y_axis), load3(l, m.z_axis)];
    let [x, y, z] = columns;
    x * v.lane(0) + y * v.lane(1) + z * v.lane(2)
}

#[cfg(test)]
mod tests {
    use glam::{DQuat, DVec3};

    use super::*;
    use crate::physics::dynamics::body::{BodyDesc, BodyId};
    use crate::physics::geometry::shape::Shape;
    use crate::physics::joints::desc::JointDesc;
    use crate::physics::joints::joint::Joint;
    use crate::physics::joints::solve::{self, NextSubstep};
    use crate::physics::solver::lanes::Portable;
    use crate::physics::solver::soft::{SoftSolverSettings, Softness};
    use crate::physics::solver::solver_bodies::SolverBodies;

    /// A fixed, two turning dynamic and a kinematic body, and ball joints between each
    /// dynamic one and every other body, with impulses remembered from a last step.
    fn scene() -> (Vec<RigidBody>, SolverBodies, Vec<Option<Joint>>) {
        let cuboid = |h: f64| Shape::cuboid(DVec3::new(h, 0.7 * h, 1.3 * h));
        let descs = [
            BodyDesc::fixed(cuboid(1.0)).at(DVec3::new(0.0, -2.0, 0.0)),
            BodyDesc::dynamic(cuboid(0.5))
                .rotated(DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.2, 0.7))
                .with_velocity(DVec3::new(0.4, -1.1, 0.2))
                .with_angular_velocity(DVec3::new(1.3, 0.2, -0.9)),
            BodyDesc::dynamic(cuboid(0.3))
                .at(DVec3::new(0.9, 0.4, -0.1))
                .rotated(DQuat::from_euler(glam::EulerRot::XYZ, -0.5, 0.1, 0.2))
                .with_angular_velocity(DVec3::new(-0.2, 2.1, 0.4)),
            BodyDesc::kinematic(cuboid(0.4))
                .at(DVec3::new(-1.0, 0.3, 0.2))
                .with_velocity(DVec3::new(0.0, 0.5, -0.3)),
        ];
        let bodies: Vec<RigidBody> = (descs.iter())
            .map(|d| RigidBody::from_desc(d).expect("valid"))
            .collect();
        let mut slots = SolverBodies::default();
        slots.assign(&bodies, &[1, 2, 3]);
        let pairs = [(0, 1), (1, 2), (2, 0), (3, 1), (2, 3)];
        let joints = (pairs.iter().enumerate())
            .map(|(k, &(a, b))| {
                let anchor = 0.5 * (bodies[a].position + bodies[b].position);
                let desc = JointDesc::ball(BodyId::new(a, 0), BodyId::new(b, 0), anchor);
                let mut joint = Joint::new(&desc, &bodies[a], &bodies[b]);
                joint.impulses.point = DVec3::new(0.3, -1.2, 0.7) * (k as f64 + 1.0);
                Some(joint)
            })
            .collect();
        (bodies, slots, joints)
    }

    /// A step's first warm start, then both passes of a substep, the relax pass holding the
    /// next warm start, through the general rows (`general`) or the lanes; the slots after
    /// them, the joints' impulses, and what those put on b as `solve::finish` reads it.
    fn passes<L: Lanes>(l: L, general: bool) -> (SolverBodies, Vec<DVec3>) {
        let (bodies, mut slots, joints) = scene();
        let mut prepared = Vec::new();
        solve::prepare(&mut prepared, &joints, &bodies, &slots);
        for c in &prepared {
            if general {
                solve::hold_general(c, &mut slots.slots, &bodies);
            } else {
                hold_warm_start(l, c, &mut slots.slots, &bodies);
            }
        }
        let h = 1.0 / 480.0;
        let biased = RowPass {
            softness: Some(Softness::of_joints(&SoftSolverSettings::default(), h)),
            h,
        };
        let relax = RowPass { softness: None, h };
        for (pass, next) in [(biased, NextSubstep::None), (relax, NextSubstep::WarmStart)] {
            for c in prepared.iter_mut() {
                if general {
                    solve::solve_general(c, &mut slots.slots, &bodies, pass, next);
                } else {
                    solve_ball(l, c, &mut slots.slots, &bodies, pass, next);
                }
            }
        }
        let mut impulses: Vec<DVec3> = prepared.iter().map(|c| c.joint.impulses.point).collect();
        for c in &prepared {
            impulses.extend(if general {
                solve::impulse_on_b_general(c, &slots.slots, &bodies)
            } else {
                impulse_on_b(l, c, &slots.slots, &bodies)
            });
        }
        (slots, impulses)
    }

    fn assert_same(x: &(SolverBodies, Vec<DVec3>), y: &(SolverBodies, Vec<DVec3>)) {
        // Debug prints each number exactly (shortest round trip), signed zeros too.
        assert_eq!(format!("{:?}", x.0.slots), format!("{:?}", y.0.slots));
        assert_eq!(format!("{:?}", x.1), format!("{:?}", y.1));
    }

    #[test]
    fn lanes_compute_the_general_rows_bits() {
        let general = passes(Portable, true);
        assert_same(&general, &passes(Portable, false));
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = crate::physics::solver::lanes::Avx2::detect() {
            assert_same(&general, &passes(avx, false));
        }
        // The passes did something: the first dynamic body's momentum moved.
        let (bodies, _, _) = scene();
        let moved = general.0.slots[1].linear_momentum.to_vec3();
        assert!(moved.distance(bodies[1].linear_momentum) > 1e-3, "{moved}");
    }
}
