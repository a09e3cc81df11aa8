//! C5 incline: a 0.5 m box released on a slope (tests/soft_solver.rs, tests/classic.rs).
//! Slide case, 40° with μ = 0.3 (tan θ > μ): the error is the relative error of the mean
//! acceleration over a 1 s run against g (sin θ − μ cos θ). Stick case, 20° with μ = 0.5
//! (tan θ < μ): reported beside each configuration, it must not move.

use glam::{DQuat, DVec3};

use super::{Case, Config, add, grounded, material, relative_error, run_for};
use rigid::physics::dynamics::forces::STANDARD_GRAVITY;
use rigid::physics::{BodyDesc, BodyId, Shape, World};

/// (slope in degrees, μ).
const SLIDE: (f64, f64) = (40.0, 0.3);
const STICK: (f64, f64) = (20.0, 0.5);
/// The contact settles for this long before the measurement starts, s.
const SETTLE: f64 = 0.1;
const SLIDE_SECONDS: f64 = 1.0;
const STICK_SECONDS: f64 = 2.0;
/// The stick case sticks if the box moves less than this over its run, m (as its tests).
const STICK_TOLERANCE: f64 = 1e-3;

pub const CASE: Case = Case {
    check: Some(("stick case (20°, μ = 0.5, 2 s)", stick)),
    ..Case::new(
        "C5 incline 40°, μ = 0.3, relative error of the acceleration",
        "c5_incline",
        SETTLE + SLIDE_SECONDS,
        run,
    )
};

/// The box resting on a slope of `degrees` with friction `mu`, after the settle, and the
/// unit vector down the slope.
fn incline(config: &Config, degrees: f64, mu: f64) -> (World, BodyId, DVec3) {
    let theta = degrees.to_radians();
    let up = DVec3::new(-theta.sin(), theta.cos(), 0.0);
    let mut world = grounded(config, up, material(0.0, mu));
    let half = DVec3::splat(0.25);
    let block = BodyDesc::dynamic(Shape::cuboid(half))
        .at(up * half.y)
        .rotated(DQuat::from_rotation_arc(DVec3::Y, up))
        .with_material(material(0.0, mu));
    let block = add(&mut world, block);
    run_for(&mut world, SETTLE, config.dt, |_| {});
    (world, block, DVec3::new(-theta.cos(), -theta.sin(), 0.0))
}

/// The acceleration is read from the distance slid, s = v0 t + a t²/2, as the tests do,
/// rather than from the velocity: the velocity gains exactly a dt per step in both
/// pipelines, and it is the integration of the position that differs between
/// configurations.
fn run(config: &Config) -> f64 {
    let (degrees, mu) = SLIDE;
    let (mut world, block, downhill) = incline(config, degrees, mu);
    let (start, start_speed) = {
        let body = world.body(block);
        (body.position, body.velocity().dot(downhill))
    };
    run_for(&mut world, SLIDE_SECONDS, config.dt, |_| {});
    let slid = (world.body(block).position - start).dot(downhill);
    let t = SLIDE_SECONDS;
    let measured = 2.0 * (slid - start_speed * t) / (t * t);
    let theta = degrees.to_radians();
    relative_error(
        measured,
        STANDARD_GRAVITY * (theta.sin() - mu * theta.cos()),
    )
}

fn stick(config: &Config) -> String {
    let (degrees, mu) = STICK;
    let (mut world, block, _) = incline(config, degrees, mu);
    let start = world.body(block).position;
    run_for(&mut world, STICK_SECONDS, config.dt, |_| {});
    let moved = (world.body(block).position - start).length();
    if moved < STICK_TOLERANCE {
        format!("sticks (moved {moved:.1e} m)")
    } else {
        format!("**slides** ({moved:.3} m)")
    }
}
