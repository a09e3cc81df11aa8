use glam::{DQuat, DVec3};

use super::constraint::{Contacts, MAX_PARTS, PointAnchors, PointConstraint, PointImpact};
use super::prepare::{SlotMotion, pair_with_previous, prepare};
#[cfg(target_arch = "x86_64")]
use super::solve::run_pass_avx2;
use super::solve::{Pass, Softness, run_pass_inline};
use super::{ContactInput, SoftSolverSettings, WarmImpulse};
use crate::physics::dynamics::body::{BodyDesc, RigidBody};
use crate::physics::geometry::shape::Shape;
use crate::physics::solver::impulse::tangent_basis;
#[cfg(target_arch = "x86_64")]
use crate::physics::solver::lanes::Avx2;
use crate::physics::solver::lanes::{F64x4, Lanes, Portable};
use crate::physics::solver::solver_bodies::{SharedBodies, SolverBodies};

/// The contacts' spring at the default settings for substeps of `h`.
fn softness(h: f64) -> Softness {
    Softness::of_contacts(&SoftSolverSettings::default(), h)
}

/// The slots opened to one thread.
fn one_thread(slots: &mut SolverBodies) -> SharedBodies<'_> {
    // SAFETY: the tests use them on one thread.
    unsafe { SharedBodies::new(&mut slots.slots) }
}

/// A scene's bodies, their slots, and its contacts prepared.
type Scene = (Vec<RigidBody>, SolverBodies, Prepared);

/// Prepared contact points: the constraints, their anchors and their impacts.
#[derive(Debug)]
struct Prepared {
    points: Vec<PointConstraint>,
    anchors: Vec<PointAnchors>,
    impacts: Vec<PointImpact>,
}

impl Prepared {
    fn contacts(&mut self) -> Contacts<'_> {
        Contacts {
            points: &mut self.points,
            anchors: &self.anchors,
            impacts: &mut self.impacts,
        }
    }
}

/// Two turning, moving boxes on a fixed one, with contacts at skew points and
/// remembered impulses, prepared as a step would.
fn scene() -> Scene {
    scene_prepared_with(Portable)
}

fn scene_prepared_with<L: Lanes>(l: L) -> Scene {
    let cuboid = |h: f64| Shape::cuboid(DVec3::new(h, 0.7 * h, 1.3 * h));
    let descs = [
        BodyDesc::fixed(cuboid(5.0)).at(DVec3::new(0.0, -3.5, 0.0)),
        BodyDesc::dynamic(cuboid(0.5))
            .rotated(DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.2, 0.7))
            .with_velocity(DVec3::new(0.4, -1.1, 0.2))
            .with_angular_velocity(DVec3::new(1.3, 0.2, -0.9)),
        BodyDesc::dynamic(cuboid(0.3))
            .at(DVec3::new(0.2, 0.9, -0.1))
            .rotated(DQuat::from_euler(glam::EulerRot::XYZ, -0.5, 0.1, 0.2))
            .with_velocity(DVec3::new(-0.3, 0.5, 0.1))
            .with_angular_velocity(DVec3::new(-0.2, 2.1, 0.4)),
    ];
    let bodies: Vec<RigidBody> = descs
        .iter()
        .map(|d| RigidBody::from_desc(d).expect("valid"))
        .collect();
    let mut slots = SolverBodies::default();
    slots.assign(&bodies, &[1, 2]);
    let point = |k: f64| DVec3::new(0.1 * k, 0.3 - 0.2 * k, -0.05 * k);
    let contact = |a: usize, b: usize, k: f64| ContactInput {
        a,
        b,
        levers: [point(k) - bodies[a].position, point(k) - bodies[b].position],
        normal: DVec3::new(0.1, 1.0, -0.2 * k).normalize(),
        separation: 0.01 - 0.004 * k,
        warm_impulse: WarmImpulse {
            normal: 0.8 * k,
            tangent: [0.1 * k, -0.05],
        },
    };
    // The first two share no moving body: a pass solves them side by side.
    let contacts = [
        contact(0, 1, 1.0),
        contact(0, 2, 4.0),
        contact(0, 1, 2.0),
        contact(1, 2, 3.0),
    ];
    let mut motions = Vec::new();
    SlotMotion::gather(&mut motions, &bodies, &[1, 2], &[]);
    let (mut points, mut anchors, mut impacts) = (Vec::new(), Vec::new(), Vec::new());
    for c in &contacts {
        let (point, anchor, impact) = prepare(
            l,
            &bodies,
            &slots,
            c,
            tangent_basis(c.normal),
            &motions,
            1.0 / 60.0,
        );
        points.push(point);
        anchors.push(anchor);
        impacts.push(impact);
    }
    for k in 0..points.len() {
        pair_with_previous(&mut points, k);
    }
    assert!(points[0].pairs_with_next && !points[2].pairs_with_next);
    let prepared = Prepared {
        points,
        anchors,
        impacts,
    };
    (bodies, slots, prepared)
}

/// The warm start gathered from the change in momenta is what adding up every contact's
/// final impulse gives (the sum the relax pass used to build contact by contact).
#[test]
fn gathered_warm_start_is_the_sum_of_the_final_impulses() {
    let (mut bodies, mut slots, mut prepared) = scene();
    let h = 1.0 / 480.0;
    for c in &prepared.points {
        slots.add_warm_start(Portable, c.warm_start_pushes(Portable));
    }
    slots.integrate_velocities_and_warm_start(&mut bodies, |_, _| {});
    let biased = Pass::Biased {
        softness: softness(h),
        max_push_out: 3.0,
        deep_points: false,
    };
    for pass in [biased, Pass::Relax] {
        run_pass_inline(
            Portable,
            pass,
            &one_thread(&mut slots),
            prepared.contacts(),
            h,
        );
    }
    slots.store_warm_start(&mut bodies, true);
    let mut summed = slots.clone();
    for slot in &mut summed.slots {
        slot.warm_start = [F64x4::ZERO; 2];
    }
    for c in &prepared.points {
        summed.add_warm_start(Portable, c.warm_start_pushes(Portable));
    }
    let mut pushed = 0.0;
    for (gathered, summed) in slots.slots[1..].iter().zip(&summed.slots[1..]) {
        for k in 0..2 {
            let (x, y) = (
                gathered.warm_start[k].to_vec3(),
                summed.warm_start[k].to_vec3(),
            );
            // Round-off of two sums of a few terms of order 10.
            assert!(
                x.distance(y) < 1e-12 * (1.0 + y.length()),
                "{x} against {y}"
            );
            pushed += y.length();
        }
    }
    assert!(pushed > 1.0, "the contacts push: {pushed}");
}

#[test]
fn packed_and_unpacked_preparation_compute_the_same_bits() {
    #[cfg(target_arch = "x86_64")]
    if let Some(avx) = Avx2::detect() {
        let (_, _, portable) = scene();
        let (_, _, packed) = scene_prepared_with(avx);
        // Debug prints each number exactly (shortest round trip), signed zeros too.
        assert_eq!(format!("{portable:?}"), format!("{packed:?}"));
    }
}

#[test]
fn packed_and_unpacked_passes_compute_the_same_bits() {
    #[cfg(target_arch = "x86_64")]
    if let Some(avx) = Avx2::detect() {
        let softness = softness(1.0 / 480.0);
        let passes = [
            Pass::Biased {
                softness,
                max_push_out: 3.0,
                deep_points: false,
            },
            Pass::Relax,
        ];
        let (_, mut slots_inline, mut inline) = scene();
        let (_, mut slots_packed, mut packed) = scene();
        for pass in passes {
            let h = 1.0 / 480.0;
            let contacts = inline.contacts();
            run_pass_inline(Portable, pass, &one_thread(&mut slots_inline), contacts, h);
            let contacts = packed.contacts();
            // SAFETY: the processor has AVX2, as `avx` proves.
            unsafe { run_pass_avx2(avx, pass, &one_thread(&mut slots_packed), contacts, h) };
        }
        for (x, y) in slots_inline.slots.iter().zip(&slots_packed.slots) {
            assert_eq!(x.linear_momentum, y.linear_momentum);
            assert_eq!(x.angular_momentum, y.angular_momentum);
        }
        for (x, y) in inline.points.iter().zip(&packed.points) {
            assert_eq!((x.impulse, x.separation), (y.impulse, y.separation));
        }
        // The passes did something: the momenta moved from where the bodies had them.
        let (bodies, _, _) = scene();
        assert_ne!(
            slots_inline.slots[1].linear_momentum.to_vec3(),
            bodies[1].linear_momentum
        );
    }
}

/// A split for the threads keeps every point once, in order, and never cuts a manifold.
#[test]
fn a_split_covers_every_point_and_cuts_no_manifold() {
    // Manifolds of 1 to 4 points between distinct pairs of slots.
    let mut points = Vec::new();
    for m in 0..50u32 {
        for _ in 0..=(m % 4) {
            let point = PointConstraint {
                slots: [m + 1, m + 2],
                ..PointConstraint::default()
            };
            points.push(point);
        }
    }
    let anchors = vec![PointAnchors::default(); points.len()];
    let mut impacts = vec![PointImpact::default(); points.len()];
    for parts in [1, 3, 8, 1000] {
        let mut copy = points.clone();
        let contacts = Contacts {
            points: &mut copy,
            anchors: &anchors,
            impacts: &mut impacts,
        };
        let split = contacts.split(parts);
        assert!(split.len() <= parts.min(MAX_PARTS), "{} parts", split.len());
        let slots: Vec<[u32; 2]> = split
            .iter()
            .flat_map(|part| part.points.iter().map(|p| p.slots))
            .collect();
        assert_eq!(slots, points.iter().map(|p| p.slots).collect::<Vec<_>>());
        for pair in split.windows(2) {
            let (last, first) = (pair[0].points.last(), pair[1].points.first());
            assert_ne!(last.map(|p| p.slots), first.map(|p| p.slots));
        }
        for part in &split {
            assert_eq!(part.points.len(), part.anchors.len());
            assert_eq!(part.points.len(), part.impacts.len());
        }
    }
}
