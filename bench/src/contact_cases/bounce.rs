//! C2 bounce: a 0.1 m ball dropped 1 m onto the ground with ε = 0.8 (tests/soft_solver.rs,
//! tests/classic.rs). The error is the largest relative error of the first three apex
//! heights against h ε^(2k); 1 if the ball bounces fewer than three times.

use glam::DVec3;

use super::{Case, Config, add, grounded, material, relative_error, run_for};
use rigid::physics::{BodyDesc, Shape};

const SECONDS: f64 = 4.0;
const RADIUS: f64 = 0.1;
const DROP: f64 = 1.0;
const RESTITUTION: f64 = 0.8;

pub const CASE: Case = Case::new(
    "C2 bounce, worst relative apex error of bounces 1–3",
    "c2_bounce",
    SECONDS,
    run,
);

fn run(config: &Config) -> f64 {
    // The ground's ε = 1: a pair takes the smaller, so the ball's 0.8 is the one that acts.
    let mut world = grounded(config, DVec3::Y, material(1.0, 0.0));
    let ball = BodyDesc::dynamic(Shape::sphere(RADIUS))
        .at(DVec3::Y * (RADIUS + DROP))
        .with_material(material(RESTITUTION, 0.0));
    let ball = add(&mut world, ball);
    let mut apexes = Vec::new();
    let mut previous_vy = 0.0;
    // The apex is read at the step where the vertical velocity turns downwards.
    run_for(&mut world, SECONDS, config.dt, |world| {
        let vy = world.body(ball).velocity().y;
        if previous_vy > 0.0 && vy <= 0.0 {
            apexes.push(world.body(ball).position.y - RADIUS);
        }
        previous_vy = vy;
    });
    if apexes.len() < 3 {
        return 1.0;
    }
    (0..3)
        .map(|k| relative_error(apexes[k], DROP * RESTITUTION.powi(2 * (k as i32 + 1))))
        .fold(0.0, f64::max)
}
