//! A ball dropped from 10 m onto a floor: prints its height as it falls, bounces and
//! settles. `cargo run --example hello_world`

use rigid::prelude::*;

fn main() -> Result<(), AddBodyError> {
    let mut world = World::default();
    world.forces.push(EnvironmentForce::earth_gravity());
    let floor = Shape::cuboid(DVec3::new(5.0, 0.5, 5.0));
    world.add_body(BodyDesc::fixed(floor).at(DVec3::new(0.0, -0.5, 0.0)))?;
    let bouncy = Material {
        restitution: 0.5,
        ..Material::default()
    };
    let ball = BodyDesc::dynamic(Shape::sphere(0.5))
        .at(DVec3::new(0.0, 10.0, 0.0))
        .with_material(bouncy);
    let ball = world.add_body(ball)?;

    let dt = 1.0 / 60.0;
    for step in 0..=240 {
        if step % 12 == 0 {
            let body = world.body(ball);
            println!(
                "t = {:4.2} s   height = {:6.3} m   speed = {:6.3} m/s{}",
                world.time(),
                body.position.y,
                body.velocity().length(),
                if body.sleeping { "   (asleep)" } else { "" }
            );
        }
        world.step(dt);
    }
    Ok(())
}
