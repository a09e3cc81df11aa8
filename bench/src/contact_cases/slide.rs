//! C4 slide: a 0.5 m box sliding at 5 m/s on the ground with μ = 0.5 (tests/soft_solver.rs,
//! tests/classic.rs). The error is the relative error of the stopping distance against
//! v²/(2 μ g).

use glam::DVec3;

use super::{Case, Config, add, grounded, material, relative_error, run_for};
use rigid::physics::dynamics::forces::STANDARD_GRAVITY;
use rigid::physics::{BodyDesc, Shape};

/// The box stops after v / (μ g) = 1.02 s; the rest checks that it stays stopped.
const SECONDS: f64 = 3.0;
const FRICTION: f64 = 0.5;
const SPEED: f64 = 5.0;

pub const CASE: Case = Case::new(
    "C4 slide, relative error of the stopping distance",
    "c4_slide",
    SECONDS,
    run,
);

fn run(config: &Config) -> f64 {
    let mut world = grounded(config, DVec3::Y, material(0.0, FRICTION));
    let half = DVec3::splat(0.25);
    let block = BodyDesc::dynamic(Shape::cuboid(half))
        .at(DVec3::Y * half.y)
        .with_velocity(DVec3::X * SPEED)
        .with_material(material(0.0, FRICTION));
    let block = add(&mut world, block);
    run_for(&mut world, SECONDS, config.dt, |_| {});
    let expected = SPEED * SPEED / (2.0 * FRICTION * STANDARD_GRAVITY);
    relative_error(world.body(block).position.x, expected)
}
