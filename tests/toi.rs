//! Bisection rewind and conservative advancement against known contact times.

mod common;

use common::*;
use glam::{DMat3, DQuat, DVec3};
use proptest::prelude::*;
use rigid::physics::dynamics::integrate::integrate_body;
use rigid::physics::{
    Aabb, BodyDesc, Integrator, Motion, RigidBody, Shape, bisection_rewind,
    conservative_advancement, gjk_distance, swept_aabb,
};

const DT: f64 = 1.0 / 60.0;

fn ground() -> RigidBody {
    RigidBody::from_desc(&BodyDesc::fixed(Shape::cuboid(DVec3::new(5.0, 0.5, 5.0)))).unwrap()
}

/// A body falling at `speed` from `height` while spinning at `spin`, one step later.
fn falling(
    shape: Shape,
    height: f64,
    speed: f64,
    spin: DVec3,
    integrator: Integrator,
) -> (RigidBody, RigidBody) {
    let desc = BodyDesc::dynamic(shape)
        .at(DVec3::new(0.3, height, -0.2))
        .with_velocity(DVec3::new(0.0, -speed, 0.0))
        .with_angular_velocity(spin);
    let start = RigidBody::from_desc(&desc).unwrap();
    let mut end = start.clone();
    integrate_body(&mut end, DT, integrator);
    (start, end)
}

/// Sphere (spinning about z) and cube (spinning about y) falling onto a box without gravity:
/// the bottom reaches the top face y = 0.5 at t = gap / speed exactly, and the orientation
/// then is the start orientation turned by ω t.
#[test]
fn rewind_finds_the_analytic_contact_time_with_positions_and_orientations() {
    let theta = 1e-4;
    let speed = 10.0;
    let gap = 0.1;
    let cases = [
        (Shape::sphere(0.5), DVec3::new(0.0, 0.0, 3.0)),
        (Shape::cuboid(DVec3::splat(0.5)), DVec3::new(0.0, 2.0, 0.0)),
    ];
    for integrator in [Integrator::ExactRotation, Integrator::Midpoint] {
        for (shape, spin) in cases.clone() {
            let (start, mut body) = falling(shape, 1.0 + gap, speed, spin, integrator);
            let mut floor = ground();
            assert!(
                gjk_distance(&floor, &body).intersecting,
                "penetrates after the step"
            );
            let rewind = bisection_rewind(&mut floor, &mut body, DT, theta, integrator);
            assert!(rewind.converged);
            let distance = gjk_distance(&floor, &body).distance;
            assert!(distance > 0.0 && distance <= theta, "distance {distance}");
            assert!((rewind.distance - distance).abs() < 1e-15);
            let expected_time = gap / speed;
            assert!(
                (rewind.time_of_impact - expected_time).abs() <= theta / speed,
                "toi {} expected {expected_time}",
                rewind.time_of_impact
            );
            let t = rewind.time_of_impact;
            let expected_position = start.position + start.velocity() * t;
            assert!(body.position.distance(expected_position) < 1e-12);
            let expected_orientation =
                DMat3::from_quat(DQuat::from_scaled_axis(spin * t)) * start.orientation;
            let error = (body.orientation - expected_orientation)
                .to_cols_array()
                .iter()
                .map(|e| e.abs())
                .fold(0.0, f64::max);
            assert!(error < 1e-12, "orientation error {error}");
            // Momenta are rewound too: unchanged here since no force acts.
            assert!(body.velocity().distance(start.velocity()) < 1e-12);
            println!(
                "{integrator:?} {}: toi {:.9} (exact {expected_time}), distance {distance:.3e}, {} iterations",
                body.shape.kind_name(),
                rewind.time_of_impact,
                rewind.iterations
            );
        }
    }
}

#[test]
fn rewind_with_gravity_lands_within_theta() {
    let theta = 1e-5;
    let gravity = DVec3::new(0.0, -9.81, 0.0);
    let (_, mut body) = falling(
        Shape::cuboid(DVec3::new(0.3, 0.2, 0.4)),
        0.71,
        3.0,
        DVec3::new(1.0, 0.5, 0.0),
        Integrator::Midpoint,
    );
    body.force = gravity * body.mass();
    let mut floor = ground();
    assert!(gjk_distance(&floor, &body).intersecting);
    let rewind = bisection_rewind(&mut floor, &mut body, DT, theta, Integrator::Midpoint);
    assert!(rewind.converged);
    let distance = gjk_distance(&floor, &body).distance;
    assert!(distance > 0.0 && distance <= theta);
    assert!(rewind.time_of_impact > 0.0 && rewind.time_of_impact < DT);
}

#[test]
fn rewind_reports_overlap_at_step_start() {
    let mut floor = ground();
    let (_, mut body) = falling(
        Shape::sphere(0.5),
        0.9,
        0.1,
        DVec3::ZERO,
        Integrator::Midpoint,
    );
    let rewind = bisection_rewind(&mut floor, &mut body, DT, 1e-4, Integrator::Midpoint);
    assert!(!rewind.converged);
    assert_eq!(rewind.time_of_impact, 0.0);
}

/// C11: a 1 cm sphere at 300 m/s against a 5 cm static wall at dt = 1/60. A discrete step
/// jumps 5 m, straight through the wall; the swept box sees the wall and conservative
/// advancement stops the sphere in front of it.
#[test]
fn fast_small_sphere_never_passes_the_thin_wall() {
    let theta = 1e-4;
    let wall = RigidBody::from_desc(
        &BodyDesc::fixed(Shape::cuboid(DVec3::new(0.025, 1.0, 1.0)))
            .at(DVec3::new(0.025, 0.0, 0.0)),
    )
    .unwrap();
    let ball = RigidBody::from_desc(
        &BodyDesc::dynamic(Shape::sphere(0.01))
            .at(DVec3::new(-1.0, 0.0, 0.0))
            .with_velocity(DVec3::new(300.0, 0.0, 0.0)),
    )
    .unwrap();
    let mut after = ball.clone();
    integrate_body(&mut after, DT, Integrator::Midpoint);
    assert!(after.position.x > 3.9);
    assert!(
        !Aabb::of_body(&after).overlaps(&Aabb::of_body(&wall)),
        "the discrete test misses"
    );
    assert!(swept_aabb(&ball, DT).overlaps(&swept_aabb(&wall, DT)));

    let hit = conservative_advancement(&ball, &wall, DT, theta).expect("an impact");
    let exact = (1.0 - 0.01) / 300.0;
    assert!(
        hit.time <= exact && exact - hit.time <= theta / 300.0,
        "toi {} exact {exact}",
        hit.time
    );
    assert!(hit.distance > 0.0 && hit.distance <= theta);
    let center = ball.position.x + 300.0 * hit.time;
    assert!(
        center + 0.01 <= 0.0 && center + 0.01 >= -theta,
        "sphere front at {}",
        center + 0.01
    );
    assert!(hit.normal.distance(DVec3::X) < 1e-12);
    println!(
        "C11: toi {:.9} s (exact {exact:.9}), gap {:.3e} m, {} iterations",
        hit.time, hit.distance, hit.iterations
    );
    // Moving away, or too slow to arrive within the step: no impact.
    let mut away = ball.clone();
    away.set_velocity(DVec3::new(-300.0, 0.0, 0.0));
    assert!(conservative_advancement(&away, &wall, DT, theta).is_none());
    let mut slow = ball.clone();
    slow.set_velocity(DVec3::new(1.0, 0.0, 0.0));
    assert!(conservative_advancement(&slow, &wall, DT, theta).is_none());
}

fn vec3(r: f64) -> impl Strategy<Value = DVec3> {
    (-r..r, -r..r, -r..r).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(100))]

    /// Fast tumbling boxes and a thin plate: whenever an impact is reported the shapes are
    /// apart by at most the tolerance at that time; and when none is reported, sampling the
    /// motion finely never finds them overlapping.
    #[test]
    fn advancement_is_conservative(v in vec3(200.0), w in vec3(30.0), start in vec3(2.0), r in vec3(1.0)) {
        let theta = 1e-4;
        let plate = body(Shape::cuboid(DVec3::new(1.0, 0.02, 1.0)), DVec3::ZERO, DQuat::IDENTITY, Motion::Static);
        let mut mover = body(Shape::cuboid(DVec3::new(0.1, 0.05, 0.2)), start + DVec3::Y * 2.5, rotation_from(r), Motion::Dynamic);
        mover.set_velocity(v);
        mover.set_angular_velocity(w);
        let motion = rigid::physics::solver::toi::BallisticMotion::of_body(&mover);
        let shape_at = |t: f64| {
            let (origin, rotation) = motion.pose_at(t);
            rigid::physics::PosedShape::new(&mover.shape, origin, rotation)
        };
        let plate_pose = rigid::physics::PosedShape::of_body(&plate);
        match conservative_advancement(&plate, &mover, DT, theta) {
            Some(hit) => {
                let d = gjk_distance(&plate_pose, &shape_at(hit.time)).distance;
                prop_assert!(d <= theta && (d > 0.0 || hit.time == 0.0), "distance {d}");
                for k in 0..200 {
                    let t = hit.time * k as f64 / 200.0;
                    prop_assert!(!gjk_distance(&plate_pose, &shape_at(t)).intersecting);
                }
            }
            None => {
                for k in 0..=400 {
                    let t = DT * k as f64 / 400.0;
                    prop_assert!(!gjk_distance(&plate_pose, &shape_at(t)).intersecting, "missed at {t}");
                }
            }
        }
    }
}
