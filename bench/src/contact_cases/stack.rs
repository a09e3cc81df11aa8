//! C9 stack: ten 0.5 m boxes stacked on the ground (tests/world_contacts.rs), run for 10 s
//! with sleeping off, so that every step counts. The error is the worst distance any box
//! moved from its start, over the box size; the test asserts less than 1 cm (0.02 here).

use glam::DVec3;

use super::{Case, Config, add, drift_over_size, grounded, material};
use rigid::physics::{BodyDesc, Shape};

const SECONDS: f64 = 10.0;
const HALF: f64 = 0.25;
const BOXES: usize = 10;

pub const CASE: Case = Case::new(
    "C9 stack of 10 boxes, worst drift after 10 s over the box size",
    "c9_stack",
    SECONDS,
    run,
);

fn run(config: &Config) -> f64 {
    let mut world = grounded(config, DVec3::Y, material(0.0, 0.5));
    let boxes: Vec<_> = (0..BOXES)
        .map(|i| {
            let at = DVec3::Y * (HALF + 2.0 * HALF * i as f64);
            let block = BodyDesc::dynamic(Shape::cuboid(DVec3::splat(HALF)))
                .at(at)
                .with_material(material(0.0, 0.5));
            add(&mut world, block)
        })
        .collect();
    drift_over_size(&mut world, &boxes, config, SECONDS, 2.0 * HALF)
}
