//! C10 pyramid: 20 layers of 0.5 m boxes, 210 in all, 5 % gaps within a layer
//! (tests/world_contacts.rs), run for 4 s with sleeping off. The error is the worst distance
//! any box moved from its start, over the box size; the test asserts less than 1 cm (0.02).

use glam::DVec3;

use super::{Case, Config, add, drift_over_size, grounded, material};
use rigid::physics::{BodyDesc, Shape};

const SECONDS: f64 = 4.0;
const HALF: f64 = 0.25;
const LAYERS: usize = 20;

pub const CASE: Case = Case::new(
    "C10 pyramid of 20 layers, worst drift after 4 s over the box size",
    "c10_pyramid",
    SECONDS,
    run,
);

fn run(config: &Config) -> f64 {
    let mut world = grounded(config, DVec3::Y, material(0.0, 0.5));
    let mut boxes = Vec::new();
    for layer in 0..LAYERS {
        let count = LAYERS - layer;
        for i in 0..count {
            let x = (i as f64 - (count - 1) as f64 / 2.0) * 2.0 * HALF * 1.05;
            let y = HALF + 2.0 * HALF * layer as f64;
            let block = BodyDesc::dynamic(Shape::cuboid(DVec3::splat(HALF)))
                .at(DVec3::new(x, y, 0.0))
                .with_material(material(0.0, 0.5));
            boxes.push(add(&mut world, block));
        }
    }
    drift_over_size(&mut world, &boxes, config, SECONDS, 2.0 * HALF)
}
