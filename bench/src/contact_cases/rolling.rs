//! C6 rolling: a 0.2 m sphere launched sliding at 5 m/s on a floor with μ = 0.3
//! (tests/soft_solver.rs, tests/classic.rs). Friction slows it until it rolls; the error is
//! the relative error of the final speed against 5/7 v0.

use glam::DVec3;

use super::{Case, Config, add, grounded, material, relative_error, run_for};
use rigid::physics::{BodyDesc, Shape};

/// Sliding lasts 2 v0 / (7 μ g) = 0.49 s; the rest checks that rolling keeps the speed.
const SECONDS: f64 = 2.0;
const RADIUS: f64 = 0.2;
const SPEED: f64 = 5.0;
const FRICTION: f64 = 0.3;

pub const CASE: Case = Case::new(
    "C6 rolling, relative error of the final speed against 5/7 v0",
    "c6_rolling",
    SECONDS,
    run,
);

fn run(config: &Config) -> f64 {
    let mut world = grounded(config, DVec3::Y, material(0.0, FRICTION));
    let ball = BodyDesc::dynamic(Shape::sphere(RADIUS))
        .at(DVec3::Y * RADIUS)
        .with_velocity(DVec3::X * SPEED)
        .with_material(material(0.0, FRICTION));
    let ball = add(&mut world, ball);
    run_for(&mut world, SECONDS, config.dt, |_| {});
    relative_error(world.body(ball).velocity().x, 5.0 / 7.0 * SPEED)
}
