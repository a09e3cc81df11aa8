//! C11 tunnelling: a 1 cm sphere at 300 m/s against a 5 cm wall, no gravity, restitution 0
//! (tests/world_contacts.rs, tests/classic.rs). At 1/60 s it moves 5 m per step, a hundred
//! wall thicknesses. The error is 1 if it ever gets past the wall's near face, else its
//! deepest penetration after any step over its radius (0 if it never overlaps).

use glam::DVec3;

use super::{Case, Config, add, material, run_for, world};
use rigid::physics::{BodyDesc, Shape};

const SECONDS: f64 = 0.5;
const RADIUS: f64 = 0.01;
const SPEED: f64 = 300.0;
const WALL_X: f64 = 5.0;
const WALL_HALF_THICKNESS: f64 = 0.025;

pub const CASE: Case = Case::new(
    "C11 tunnelling, 1 cm sphere at 300 m/s, penetration over radius (1: passed)",
    "c11_tunnelling",
    SECONDS,
    run,
);

fn run(config: &Config) -> f64 {
    let mut world = world(config, false);
    let wall = BodyDesc::fixed(Shape::cuboid(DVec3::new(WALL_HALF_THICKNESS, 2.0, 2.0)))
        .at(DVec3::X * WALL_X)
        .with_material(material(0.0, 0.0));
    add(&mut world, wall);
    let bullet = BodyDesc::dynamic(Shape::sphere(RADIUS))
        .with_velocity(DVec3::X * SPEED)
        .with_material(material(0.0, 0.0));
    let bullet = add(&mut world, bullet);
    let face = WALL_X - WALL_HALF_THICKNESS;
    let mut worst: f64 = 0.0;
    // A centre past the face (depth ≥ radius), or a sphere beyond the wall, counts as 1.
    run_for(&mut world, SECONDS, config.dt, |world| {
        let depth = world.body(bullet).position.x + RADIUS - face;
        worst = worst.max((depth / RADIUS).clamp(0.0, 1.0));
    });
    worst
}
