//! Kinematic bodies: a moving platform carries a box by friction, a target pose is reached
//! in one step, nothing pushes a kinematic body, it keeps what it carries awake while it
//! moves, bodies switch between dynamic, kinematic and static, and bad uses get typed errors.

use glam::{DQuat, DVec3};
use rigid::physics::{
    BodyDesc, BodyId, EnvironmentForce, JointDesc, Material, Motion, MotionError, Pipeline, Shape,
    StepError, World,
};

const DT: f64 = 1.0 / 60.0;

fn world() -> World {
    let mut world = World::default();
    world.forces.push(EnvironmentForce::earth_gravity());
    world
}

fn rough(friction: f64) -> Material {
    Material {
        friction,
        ..Material::default()
    }
}

/// A 4 m × 4 m platform, kinematic, top face at y = 0, and a 0.5 m box resting on it.
fn platform_and_box(world: &mut World, friction: f64) -> (BodyId, BodyId) {
    let platform = BodyDesc::kinematic(Shape::cuboid(DVec3::new(2.0, 0.1, 2.0)))
        .at(DVec3::new(0.0, -0.1, 0.0))
        .with_material(rough(friction));
    let platform = world.add_body(platform).unwrap();
    let crate_ = BodyDesc::dynamic(Shape::cuboid(DVec3::splat(0.25)))
        .at(DVec3::new(0.0, 0.25, 0.0))
        .with_material(rough(friction));
    (platform, world.add_body(crate_).unwrap())
}

#[test]
fn a_moving_platform_carries_a_resting_box() {
    let mut world = world();
    let (platform, crate_) = platform_and_box(&mut world, 0.8);
    for _ in 0..30 {
        world.step(DT); // settle at rest
    }
    world
        .set_kinematic_velocity(platform, DVec3::X, DVec3::ZERO)
        .unwrap();
    for _ in 0..60 {
        world.step(DT);
    }
    let v = world.body(crate_).velocity();
    println!("box on a 1 m/s platform after 1 s: {v:?} m/s");
    assert!((v.x - 1.0).abs() < 0.01 && v.y.abs() < 1e-3, "{v}");
    let platform = world.body(platform);
    assert!(
        (platform.position.x - 1.0).abs() < 1e-9,
        "{}",
        platform.position
    );
    assert!(
        (platform.position.y + 0.1).abs() < 1e-12,
        "pushed down to {}",
        platform.position
    );
}

#[test]
fn a_slow_platform_keeps_its_load_awake() {
    let mut world = world();
    let (platform, crate_) = platform_and_box(&mut world, 0.8);
    world
        .set_kinematic_velocity(platform, DVec3::X * 0.01, DVec3::ZERO)
        .unwrap();
    for _ in 0..300 {
        world.step(DT);
    }
    assert!(!world.body(platform).sleeping && !world.body(crate_).sleeping);
    let v = world.body(crate_).velocity().x;
    assert!((v - 0.01).abs() < 1e-3, "{v} m/s");
    // Stopped, both fall asleep.
    world
        .set_kinematic_velocity(platform, DVec3::ZERO, DVec3::ZERO)
        .unwrap();
    for _ in 0..120 {
        world.step(DT);
    }
    assert!(world.body(platform).sleeping && world.body(crate_).sleeping);
}

#[test]
fn a_target_pose_is_reached_in_one_step() {
    let mut world = world();
    let paddle = BodyDesc::kinematic(Shape::cuboid(DVec3::new(1.0, 0.1, 0.1)));
    let paddle = world.add_body(paddle).unwrap();
    let (position, rotation) = (DVec3::new(0.3, 1.0, -0.2), DQuat::from_rotation_y(0.7));
    world
        .set_kinematic_target(paddle, position, rotation)
        .unwrap();
    world.step(DT);
    let body = world.body(paddle);
    let turn = body.rotation().angle_between(rotation);
    println!(
        "target: off by {:.1e} m, {turn:.1e} rad",
        body.shape_origin().distance(position)
    );
    assert!(body.shape_origin().distance(position) < 1e-12 && turn < 1e-7);
    assert_eq!(body.velocity(), DVec3::ZERO, "it stops at the target");
}

#[test]
fn a_kinematic_body_turning_bats_a_ball() {
    let mut world = World::default();
    let paddle = BodyDesc::kinematic(Shape::cuboid(DVec3::new(1.0, 0.05, 0.2)))
        .with_angular_velocity(DVec3::Y * 10.0);
    let paddle = world.add_body(paddle).unwrap();
    let ball = BodyDesc::dynamic(Shape::sphere(0.1)).at(DVec3::new(0.0, 0.0, 0.8));
    let ball = world.add_body(ball).unwrap();
    for _ in 0..60 {
        world.step(DT);
    }
    let speed = world.body(ball).velocity().length();
    println!("ball batted by a paddle at 10 rad/s: {speed:.3} m/s");
    assert!(speed > 3.0, "{speed} m/s");
    assert_eq!(world.body(paddle).angular_velocity(), DVec3::Y * 10.0);
}

#[test]
fn a_heavy_body_does_not_push_a_kinematic_one() {
    let mut world = World::default();
    let wall = BodyDesc::kinematic(Shape::cuboid(DVec3::new(0.1, 1.0, 1.0)));
    let wall = world.add_body(wall).unwrap();
    let ram = BodyDesc::dynamic(Shape::cuboid(DVec3::splat(0.5)))
        .at(DVec3::new(-3.0, 0.0, 0.0))
        .with_mass(1000.0)
        .with_velocity(DVec3::X * 10.0);
    let ram = world.add_body(ram).unwrap();
    for _ in 0..60 {
        world.step(DT);
    }
    let body = world.body(wall);
    assert_eq!(body.position, DVec3::ZERO);
    assert_eq!(body.velocity(), DVec3::ZERO);
    let v = world.body(ram).velocity().x;
    assert!(v <= 0.0, "the ram went on at {v} m/s");
    assert!(
        world.body(ram).position.x < -0.59,
        "{}",
        world.body(ram).position
    );
}

#[test]
fn a_body_switches_between_dynamic_kinematic_and_static() {
    let mut world = world();
    let body = BodyDesc::dynamic(Shape::sphere(0.5)).with_mass(2.0);
    let body = world.add_body(body).unwrap();
    world.step(DT);
    let falling = world.body(body).velocity();
    world.set_motion(body, Motion::Kinematic).unwrap();
    world.step(DT);
    assert_eq!(
        world.body(body).velocity(),
        falling,
        "gravity no longer acts"
    );
    world.set_motion(body, Motion::Static).unwrap();
    let resting = world.body(body).position;
    world.step(DT);
    assert_eq!(world.body(body).position, resting);
    world.set_motion(body, Motion::Dynamic).unwrap();
    assert_eq!(world.body(body).mass(), 2.0, "the mass it was made with");
    world.step(DT);
    assert!(world.body(body).position.y < resting.y);
}

#[test]
fn bad_uses_get_typed_errors() {
    let mut world = world();
    let dynamic = world
        .add_body(BodyDesc::dynamic(Shape::sphere(0.5)))
        .unwrap();
    let kinematic = world
        .add_body(BodyDesc::kinematic(Shape::sphere(0.5)))
        .unwrap();
    let (v, w) = (DVec3::X, DVec3::ZERO);
    assert_eq!(
        world.set_kinematic_velocity(dynamic, v, w),
        Err(MotionError::NotKinematic(dynamic.0))
    );
    assert_eq!(
        world.set_kinematic_velocity(BodyId(9), v, w),
        Err(MotionError::NoSuchBody(9))
    );
    assert_eq!(
        world.set_kinematic_velocity(kinematic, DVec3::NAN, w),
        Err(MotionError::NotFinite("velocity"))
    );
    let zero = DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0);
    assert_eq!(
        world.set_kinematic_target(kinematic, DVec3::ZERO, zero),
        Err(MotionError::NotFinite("rotation"))
    );
    assert_eq!(
        world.set_motion(dynamic, Motion::Removed),
        Err(MotionError::NotAMotion(Motion::Removed))
    );
    world.remove_body(dynamic).unwrap();
    assert_eq!(
        world.set_motion(dynamic, Motion::Kinematic),
        Err(MotionError::NoSuchBody(dynamic.0))
    );
    world.settings.pipeline = Pipeline::Classic;
    assert_eq!(world.try_step(DT), Err(StepError::KinematicNeedsSoft(1)));
}

#[test]
fn a_body_hung_from_a_kinematic_carrier_follows_it() {
    let mut world = world();
    let carrier = BodyDesc::kinematic(Shape::cuboid(DVec3::splat(0.1))).with_velocity(DVec3::X);
    let carrier = world.add_body(carrier).unwrap();
    let bob = BodyDesc::dynamic(Shape::sphere(0.1)).at(DVec3::new(0.0, -1.0, 0.0));
    let bob = world.add_body(bob).unwrap();
    let rod = JointDesc::distance(carrier, bob, DVec3::ZERO, DVec3::new(0.0, -1.0, 0.0));
    world.add_joint(rod).unwrap();
    let mut worst: f64 = 0.0;
    for _ in 0..120 {
        world.step(DT);
        let (c, b) = (world.body(carrier).position, world.body(bob).position);
        worst = worst.max((c.distance(b) - 1.0).abs());
    }
    println!(
        "bob on a carrier at 1 m/s: rod length off by {:.2e} m",
        worst
    );
    assert!(worst < 1e-3, "{worst} m");
    assert!((world.body(carrier).position.x - 2.0).abs() < 1e-9);
    assert!(world.body(bob).position.x > 1.0, "the bob was left behind");
}

#[test]
fn a_saved_world_with_kinematic_bodies_continues_bit_for_bit() {
    let mut world = world();
    let (platform, crate_) = platform_and_box(&mut world, 0.8);
    world
        .set_kinematic_velocity(platform, DVec3::X, DVec3::Y * 0.3)
        .unwrap();
    for _ in 0..20 {
        world.step(DT);
    }
    let target = (DVec3::new(0.5, 0.0, 0.0), DQuat::from_rotation_y(0.2));
    world
        .set_kinematic_target(platform, target.0, target.1)
        .unwrap();
    let text = world.to_snapshot().to_ron();
    let snapshot = rigid::physics::WorldSnapshot::from_ron(&text, "saved").unwrap();
    let mut restored = World::from_snapshot(snapshot, "saved").unwrap();
    for _ in 0..30 {
        world.step(DT);
        restored.step(DT);
    }
    assert_eq!(world.body(crate_), restored.body(crate_));
    assert_eq!(world.body(platform), restored.body(platform));
    // A kinematic body with a mass is refused.
    let mut broken = world.to_snapshot();
    broken.bodies[platform.index()].inv_mass = 1.0;
    assert!(World::from_snapshot(broken, "broken").is_err());
}
