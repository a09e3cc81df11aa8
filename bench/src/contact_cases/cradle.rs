//! C7 Newton's cradle: five 1 kg balls of 0.1 m in a row, 1 mm apart, the first arriving at
//! 1 m/s, ε = 1, no gravity (tests/classic.rs; tests/soft_solver.rs starts them touching).
//! All the momentum should pass to the last ball; the error is |v_last − v0| / v0 after 1 s.
//! The classic pipeline's time-ordered impacts pass it on; the soft solver's simultaneous
//! impulses spread it over the row, so its error stays large at any dt.

use glam::DVec3;

use super::{Case, Config, add, material, relative_error, run_for, world};
use rigid::physics::{BodyDesc, Shape};

const SECONDS: f64 = 1.0;
const RADIUS: f64 = 0.1;
const GAP: f64 = 1e-3;
const SPEED: f64 = 1.0;
const BALLS: usize = 5;

pub const CASE: Case = Case::new(
    "C7 Newton's cradle, relative error of the last ball's velocity",
    "c7_cradle",
    SECONDS,
    run,
)
.without_default_tolerance();

fn run(config: &Config) -> f64 {
    let mut world = world(config, false);
    let balls: Vec<_> = (0..BALLS)
        .map(|i| {
            let x = i as f64 * (2.0 * RADIUS + GAP) - if i == 0 { 0.05 } else { 0.0 };
            let speed = if i == 0 { SPEED } else { 0.0 };
            let ball = BodyDesc::dynamic(Shape::sphere(RADIUS))
                .with_mass(1.0)
                .at(DVec3::X * x)
                .with_velocity(DVec3::X * speed)
                .with_material(material(1.0, 0.0));
            add(&mut world, ball)
        })
        .collect();
    run_for(&mut world, SECONDS, config.dt, |_| {});
    let last = balls[BALLS - 1];
    relative_error(world.body(last).velocity().x, SPEED)
}
