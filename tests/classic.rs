//! The report's classic pipeline against analytic answers: C2 bounce, C7 Newton's cradle,
//! C8 elastic pair, C11 tunnelling, resting contact; C2 and C8 with Algorithm 4 too.

use glam::DVec3;
use rigid::physics::solver::classic::MainLoop;
use rigid::physics::{
    BodyDesc, BodyId, EnvironmentForce, Material, Pipeline, Shape, World, WorldSettings,
};

fn classic_world(gravity: bool) -> World {
    let mut world = World::new(WorldSettings {
        pipeline: Pipeline::Classic,
        ..WorldSettings::default()
    });
    world.settings.sleep.enabled = false;
    if gravity {
        world.forces.push(EnvironmentForce::earth_gravity());
    }
    world
}

fn material(restitution: f64, friction: f64) -> Material {
    Material {
        density: 1000.0,
        restitution,
        friction,
    }
}

/// A static slab whose top face is y = 0.
fn add_ground(world: &mut World, restitution: f64) -> BodyId {
    let slab = BodyDesc::fixed(Shape::cuboid(DVec3::new(20.0, 0.5, 20.0)))
        .at(DVec3::Y * -0.5)
        .with_material(material(restitution, 0.5));
    world.add_body(slab).unwrap()
}

/// The C2 ball: radius 0.1 m dropped from 1 m onto ε = 1 ground with ε = 0.8, for 4 s.
const C2_DROP: f64 = 1.0;
const C2_RESTITUTION: f64 = 0.8;

/// What a C2 run measured.
struct Bounces {
    /// Heights of the ball's lowest point at its first apexes, m.
    apexes: Vec<f64>,
    /// The largest energy after any step and the largest rise over one step, over the
    /// initial energy (mechanical: kinetic + m g y).
    max_energy: f64,
    max_rise: f64,
}

fn c2_bounces(mut world: World) -> Bounces {
    let radius = 0.1;
    add_ground(&mut world, 1.0);
    let ball = world
        .add_body(
            BodyDesc::dynamic(Shape::sphere(radius))
                .at(DVec3::Y * (radius + C2_DROP))
                .with_material(material(C2_RESTITUTION, 0.0)),
        )
        .unwrap();
    let energy = |w: &World| {
        w.body(ball).kinetic_energy() + w.body(ball).mass() * 9.81 * w.body(ball).position.y
    };
    let initial = energy(&world);
    let (mut apexes, mut previous_vy, mut previous_energy) = (vec![], 0.0, initial);
    let (mut max_energy, mut max_rise) = (f64::MIN, f64::MIN);
    for _ in 0..240 {
        world.step(1.0 / 60.0);
        let now = energy(&world);
        max_energy = max_energy.max(now / initial);
        max_rise = max_rise.max((now - previous_energy) / initial);
        previous_energy = now;
        let vy = world.body(ball).velocity().y;
        if previous_vy > 0.0 && vy <= 0.0 {
            apexes.push(world.body(ball).position.y - radius);
        }
        previous_vy = vy;
    }
    assert!(apexes.len() >= 3, "{apexes:?}");
    Bounces {
        apexes,
        max_energy,
        max_rise,
    }
}

/// Signed relative errors of the first three apexes against h ε^(2k).
fn apex_errors(bounces: &Bounces, label: &str) -> Vec<f64> {
    (0..3)
        .map(|k| {
            let expected = C2_DROP * C2_RESTITUTION.powi(2 * (k as i32 + 1));
            let error = (bounces.apexes[k] - expected) / expected;
            println!(
                "{label} bounce {}: apex {:.4} m, expected {expected:.4} m, error {:+.2} %",
                k + 1,
                bounces.apexes[k],
                error * 100.0
            );
            error
        })
        .collect()
}

#[test]
fn c2_bounce_apex_heights_with_the_classic_pipeline() {
    let mut world = classic_world(true);
    // Forces act once per slice and free flight is first order in the slice: one slice
    // (the report's) gives bounce 2 4.3 % low; 8 slices keep all three within 0.7 %.
    world.settings.classic.substeps = 8;
    let bounces = c2_bounces(world);
    for (k, error) in apex_errors(&bounces, "classic").iter().enumerate() {
        assert!(error.abs() < 0.02, "bounce {}: {error}", k + 1);
    }
    assert!(
        bounces.max_energy <= 1.0 + 1e-9,
        "energy grew: {}",
        bounces.max_energy
    );
}

fn simple_loop_world(gravity: bool, substeps: u32) -> World {
    let mut world = classic_world(gravity);
    world.settings.classic.main_loop = MainLoop::Simple;
    world.settings.classic.substeps = substeps;
    world
}

#[test]
fn c2_bounce_with_algorithm_4_is_first_order_and_never_gains_energy() {
    // Algorithm 4 answers an impact at the rewound contact, with the speed the ball really
    // had there, then integrates a whole slice: free flight is semi-implicit Euler, each
    // fall short of speed by g·h/v and each rise short of height by g·h/u (h the slice, u
    // the launch speed), and nothing offsets it. The report's single slice at dt = 1/60
    // cannot meet C2: measured 8.4, 18.4 and 30.2 % low. The error shrinks with the slice;
    // 24 slices meet C2 (measured 0.36, 0.82, 1.36 % low; 16 slices leave bounce 3 2.1 %
    // low).
    let one_slice = apex_errors(
        &c2_bounces(simple_loop_world(true, 1)),
        "algorithm 4, 1 slice",
    );
    for (error, bound) in one_slice.iter().zip([0.09, 0.19, 0.31]) {
        assert!((-bound..0.0).contains(error), "{one_slice:?}");
    }
    let fine = c2_bounces(simple_loop_world(true, 24));
    for (k, error) in apex_errors(&fine, "algorithm 4, 24 slices")
        .iter()
        .enumerate()
    {
        assert!(error.abs() < 0.02, "bounce {}: {error}", k + 1);
    }
    // Energy never increases, not even over one step (to round-off): the rewind takes the
    // momenta back with the poses instead of lifting the ball at its impact speed.
    for slices in [1, 24] {
        let bounces = c2_bounces(simple_loop_world(true, slices));
        assert!(
            bounces.max_rise <= 1e-12,
            "{slices} slices: energy rose by {} of E0 in a step",
            bounces.max_rise
        );
    }
}

#[test]
fn c7_newtons_cradle_passes_the_momentum_to_the_last_ball() {
    // Balls 1 mm apart (more than θ = 0.1 mm): the time-ordered loop treats each impact
    // as its own event, as the balls of a real cradle collide one after the other.
    let (radius, v0) = (0.1, 1.0);
    let mut world = classic_world(false);
    let balls: Vec<BodyId> = (0..5)
        .map(|i| {
            let x = i as f64 * (2.0 * radius + 1e-3) - if i == 0 { 0.05 } else { 0.0 };
            let desc = BodyDesc::dynamic(Shape::sphere(radius))
                .with_mass(1.0)
                .at(DVec3::new(x, 0.0, 0.0))
                .with_velocity(DVec3::X * if i == 0 { v0 } else { 0.0 })
                .with_material(material(1.0, 0.0));
            world.add_body(desc).unwrap()
        })
        .collect();
    for _ in 0..60 {
        world.step(1.0 / 60.0);
    }
    let velocities: Vec<f64> = balls.iter().map(|&b| world.body(b).velocity().x).collect();
    println!("C7 classic: velocities {velocities:.4?}");
    assert!(velocities[4] >= 0.95 * v0, "last ball {}", velocities[4]);
    for v in &velocities[..4] {
        assert!(v.abs() <= 0.05 * v0, "{velocities:?}");
    }
    let momentum: f64 = velocities.iter().sum();
    assert!((momentum - v0).abs() < 1e-12);
}

/// C8: masses 1 and 3 kg meeting head on at 2 and −1 m/s, ε = 1.
const C8: (f64, f64, f64, f64) = (1.0, 3.0, 2.0, -1.0);

/// Runs the C8 pair for 1 s, the left sphere starting at `left_x` (the right one at 0.5 m),
/// and checks the textbook outgoing velocities (within 1 %) and the momentum (to float
/// precision). Returns the pair's final gap, m, and how many rewinds the steps made.
fn c8_elastic_pair(mut world: World, left_x: f64) -> (f64, u32) {
    let (m1, m2, v1, v2) = C8;
    let sphere = |mass: f64, x: f64, v: f64| {
        BodyDesc::dynamic(Shape::sphere(0.1))
            .with_mass(mass)
            .at(DVec3::X * x)
            .with_velocity(DVec3::X * v)
            .with_material(material(1.0, 0.0))
    };
    let left = world.add_body(sphere(m1, left_x, v1)).unwrap();
    let right = world.add_body(sphere(m2, 0.5, v2)).unwrap();
    let mut rewinds = 0;
    for _ in 0..60 {
        world.step(1.0 / 60.0);
        rewinds += world.classic_report().rewinds;
    }
    let expected1 = ((m1 - m2) * v1 + 2.0 * m2 * v2) / (m1 + m2);
    let expected2 = ((m2 - m1) * v2 + 2.0 * m1 * v1) / (m1 + m2);
    let (out1, out2) = (
        world.body(left).velocity().x,
        world.body(right).velocity().x,
    );
    assert!(
        (out1 - expected1).abs() / expected1.abs() < 0.01,
        "{out1} vs {expected1}"
    );
    assert!(
        (out2 - expected2).abs() / expected2.abs() < 0.01,
        "{out2} vs {expected2}"
    );
    let momentum = world.body(left).linear_momentum + world.body(right).linear_momentum;
    println!(
        "C8 from {left_x} m: v1 {out1:.15} (expected {expected1}), v2 {out2:.15} (expected {expected2}), momentum error {:.1e}, {rewinds} rewinds",
        momentum.x - (m1 * v1 + m2 * v2)
    );
    assert!((momentum.x - (m1 * v1 + m2 * v2)).abs() < 1e-12);
    let gap = (world.body(right).position - world.body(left).position).length() - 0.2;
    (gap, rewinds)
}

#[test]
fn c8_elastic_pair_with_the_classic_pipeline() {
    let (gap, _) = c8_elastic_pair(classic_world(false), -0.5);
    // The spheres never overlapped: the last event left them at most θ apart or separating.
    assert!(gap > 0.0);
}

#[test]
fn c8_elastic_pair_with_algorithm_4() {
    // From ±0.5 m the 0.8 m gap closes at 3 m/s in exactly 16 steps of 1/60 s: the spheres
    // touch at the end of a step. From −0.51 m they meet mid-step and overlap after it, so
    // Algorithm 4 must rewind them to the contact before the impulse.
    for slices in [1, 8] {
        let (gap, _) = c8_elastic_pair(simple_loop_world(false, slices), -0.5);
        assert!(gap > 1.0, "{slices} slices: gap {gap}");
        let (gap, rewinds) = c8_elastic_pair(simple_loop_world(false, slices), -0.51);
        assert!(rewinds >= 1, "{slices} slices: no rewind");
        assert!(gap > 1.0, "{slices} slices: gap {gap}");
    }
}

#[test]
fn c11_no_tunnelling_with_the_classic_pipeline() {
    let mut world = classic_world(false);
    let wall = BodyDesc::fixed(Shape::cuboid(DVec3::new(0.025, 2.0, 2.0)))
        .at(DVec3::X * 5.0)
        .with_material(material(1.0, 0.0));
    world.add_body(wall).unwrap();
    let bullet = world
        .add_body(
            BodyDesc::dynamic(Shape::sphere(0.01))
                .with_velocity(DVec3::X * 300.0)
                .with_material(material(0.5, 0.0)),
        )
        .unwrap();
    for _ in 0..30 {
        world.step(1.0 / 60.0);
        assert!(
            world.body(bullet).position.x < 5.0 - 0.025,
            "tunnelled: {}",
            world.body(bullet).position.x
        );
    }
    // It bounced back at ε = 0.5 of its speed.
    assert!((world.body(bullet).velocity().x + 150.0).abs() < 1.5);
}

#[test]
fn a_box_rests_on_the_ground_with_the_classic_pipeline() {
    let mut world = classic_world(true);
    add_ground(&mut world, 0.2);
    let block = world
        .add_body(
            BodyDesc::dynamic(Shape::cuboid(DVec3::splat(0.25)))
                .at(DVec3::Y * 0.6)
                .with_material(material(0.2, 0.5)),
        )
        .unwrap();
    for _ in 0..180 {
        world.step(1.0 / 60.0);
    }
    let body = world.body(block);
    println!(
        "classic resting: y = {:.5}, v = {:.2e}, events {:?}",
        body.position.y,
        body.velocity().length(),
        world.classic_report()
    );
    assert!(
        (body.position.y - 0.25).abs() < 2e-3,
        "y = {}",
        body.position.y
    );
    assert!(body.velocity().length() < 0.2, "v = {}", body.velocity());
}

/// A static slab whose top face is the plane through the origin with normal `up`.
fn add_tilted_ground(world: &mut World, up: DVec3, friction: f64) {
    let slab = BodyDesc::fixed(Shape::cuboid(DVec3::new(20.0, 0.5, 20.0)))
        .rotated(glam::DQuat::from_rotation_arc(DVec3::Y, up))
        .at(-up * 0.5)
        .with_material(material(0.0, friction));
    world.add_body(slab).unwrap();
}

#[test]
fn c4_sliding_box_with_the_classic_pipeline() {
    let (mu, v0) = (0.5, 5.0);
    let mut world = classic_world(true);
    add_tilted_ground(&mut world, DVec3::Y, mu);
    let block = BodyDesc::dynamic(Shape::cuboid(DVec3::splat(0.25)))
        .at(DVec3::Y * 0.25)
        .with_velocity(DVec3::X * v0)
        .with_material(material(0.0, mu));
    let block = world.add_body(block).unwrap();
    for _ in 0..180 {
        world.step(1.0 / 60.0);
    }
    let expected = v0 * v0 / (2.0 * mu * 9.81);
    let distance = world.body(block).position.x;
    println!("classic C4: {distance:.4} m, expected {expected:.4} m");
    assert!((distance - expected).abs() / expected < 0.02);
}

#[test]
fn c5_incline_with_the_classic_pipeline() {
    for (theta_deg, mu) in [(20.0f64, 0.5), (40.0, 0.3)] {
        let theta = theta_deg.to_radians();
        let up = DVec3::new(-theta.sin(), theta.cos(), 0.0);
        let downhill = DVec3::new(-theta.cos(), -theta.sin(), 0.0);
        let mut world = classic_world(true);
        add_tilted_ground(&mut world, up, mu);
        let block = BodyDesc::dynamic(Shape::cuboid(DVec3::splat(0.25)))
            .at(up * 0.25)
            .rotated(glam::DQuat::from_rotation_arc(DVec3::Y, up))
            .with_material(material(0.0, mu));
        let block = world.add_body(block).unwrap();
        for _ in 0..3 {
            world.step(1.0 / 60.0);
        }
        let (start, v0) = (
            world.body(block).position,
            world.body(block).velocity().dot(downhill),
        );
        for _ in 0..60 {
            world.step(1.0 / 60.0);
        }
        let slid = (world.body(block).position - start).dot(downhill);
        let a = 9.81 * (theta.sin() - mu * theta.cos());
        println!("classic C5 {theta_deg}°: slid {slid:.4} m");
        if a <= 0.0 {
            assert!(slid.abs() < 1e-3, "should stick: {slid}");
        } else {
            let expected = v0 + 0.5 * a;
            assert!(
                (slid - expected).abs() / expected < 0.02,
                "{slid} vs {expected}"
            );
        }
    }
}

#[test]
fn c6_sliding_sphere_rolls_at_five_sevenths_with_the_classic_pipeline() {
    let mut world = classic_world(true);
    add_tilted_ground(&mut world, DVec3::Y, 0.3);
    let ball = BodyDesc::dynamic(Shape::sphere(0.2))
        .at(DVec3::Y * 0.2)
        .with_velocity(DVec3::X * 5.0)
        .with_material(material(0.0, 0.3));
    let ball = world.add_body(ball).unwrap();
    for _ in 0..120 {
        world.step(1.0 / 60.0);
    }
    let v = world.body(ball).velocity().x;
    println!("classic C6: {v:.5} m/s, expected {:.5}", 25.0 / 7.0);
    assert!((v - 25.0 / 7.0).abs() / (25.0 / 7.0) < 0.02);
}

/// A user's force and torque act over the whole step however many slices the step is cut
/// into: a free body pushed for one step of 0.1 s gains exactly F·dt and τ·dt of momentum
/// (the slices add F·dt/n n times; round-off only), in both main loops.
#[test]
fn a_user_force_acts_over_every_slice_of_the_step() {
    let dt = 0.1;
    let force = DVec3::new(3.0, -2.0, 1.5);
    let lever = DVec3::new(0.0, 0.2, 0.0);
    for main_loop in [MainLoop::Ordered, MainLoop::Simple] {
        for substeps in [1, 4] {
            let mut world = classic_world(false);
            world.settings.classic.substeps = substeps;
            world.settings.classic.main_loop = main_loop;
            let ball = BodyDesc::dynamic(Shape::sphere(0.1)).with_material(material(0.5, 0.5));
            let id = world.add_body(ball).unwrap();
            let body = world.body_mut(id);
            let point = body.position + lever;
            body.apply_force_at(force, point);
            world.step(dt);
            let body = world.body(id);
            let torque = lever.cross(force);
            let tolerance = 1e-12 * force.length() * dt;
            assert!(
                (body.linear_momentum - force * dt).length() <= tolerance,
                "{main_loop:?} ×{substeps}: p = {} against F dt = {}",
                body.linear_momentum,
                force * dt
            );
            assert!(
                (body.angular_momentum - torque * dt).length() <= tolerance,
                "{main_loop:?} ×{substeps}: L = {} against τ dt = {}",
                body.angular_momentum,
                torque * dt
            );
        }
    }
}
