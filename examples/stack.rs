//! A stack of ten boxes on a floor, stepped until it falls asleep: prints how far the top box
//! settled and when the stack slept. `cargo run --example stack`

use rigid::prelude::*;

const BOXES: usize = 10;
const HALF: f64 = 0.5;

fn main() -> Result<(), AddBodyError> {
    let mut world = World::default();
    world.forces.push(EnvironmentForce::earth_gravity());
    let floor = Shape::cuboid(DVec3::new(10.0, 0.5, 10.0));
    world.add_body(BodyDesc::fixed(floor).at(DVec3::new(0.0, -0.5, 0.0)))?;
    let mut boxes = Vec::new();
    for k in 0..BOXES {
        let centre = DVec3::new(0.0, HALF + 2.0 * HALF * k as f64, 0.0);
        let desc = BodyDesc::dynamic(Shape::cuboid(DVec3::splat(HALF)))
            .at(centre)
            .named(format!("box {k}"));
        boxes.push(world.add_body(desc)?);
    }
    let top = *boxes.last().expect("ten boxes");
    let start = world.body(top).position;

    let dt = 1.0 / 60.0;
    while world.awake_count() > 0 || world.step_count() == 0 {
        world.step(dt);
        if world.time() > 20.0 {
            println!("still awake after 20 s");
            break;
        }
    }
    let end = world.body(top).position;
    println!(
        "{BOXES} boxes: asleep after {:.2} s, the top box settled {:.2} mm and moved {:.2} mm sideways",
        world.time(),
        (start.y - end.y) * 1e3,
        (end - start).with_y(0.0).length() * 1e3,
    );
    Ok(())
}
