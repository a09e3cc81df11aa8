//! C8 elastic pair: spheres of 1 and 3 kg meeting head on at 2 and −1 m/s with ε = 1, no
//! gravity (tests/soft_solver.rs, tests/classic.rs). The error is the larger relative error
//! of the two outgoing velocities against the textbook elastic collision.

use glam::DVec3;

use super::{Case, Config, add, material, relative_error, run_for, world};
use rigid::physics::{BodyDesc, Shape};

const SECONDS: f64 = 1.0;
/// (m1, m2, v1, v2), kg and m/s.
const PAIR: (f64, f64, f64, f64) = (1.0, 3.0, 2.0, -1.0);
/// Where the spheres start, m. From ±0.5 m they would touch exactly at the end of a step at
/// every dt of the sweep (each is 1/30 s over a power of two); −0.51 m, the mid-step variant
/// of tests/classic.rs, makes them meet inside a step as they would in any real scene.
const LEFT_X: f64 = -0.51;
const RIGHT_X: f64 = 0.5;

pub const CASE: Case = Case::new(
    "C8 elastic pair, m 1:3, worst relative error of the outgoing velocities",
    "c8_elastic_pair",
    SECONDS,
    run,
);

fn run(config: &Config) -> f64 {
    let (m1, m2, v1, v2) = PAIR;
    let mut world = world(config, false);
    let sphere = |mass: f64, x: f64, v: f64| {
        BodyDesc::dynamic(Shape::sphere(0.1))
            .with_mass(mass)
            .at(DVec3::X * x)
            .with_velocity(DVec3::X * v)
            .with_material(material(1.0, 0.0))
    };
    let left = add(&mut world, sphere(m1, LEFT_X, v1));
    let right = add(&mut world, sphere(m2, RIGHT_X, v2));
    run_for(&mut world, SECONDS, config.dt, |_| {});
    let expected1 = ((m1 - m2) * v1 + 2.0 * m2 * v2) / (m1 + m2);
    let expected2 = ((m2 - m1) * v2 + 2.0 * m1 * v1) / (m1 + m2);
    let error1 = relative_error(world.body(left).velocity().x, expected1);
    error1.max(relative_error(world.body(right).velocity().x, expected2))
}
