//! Ray casts and a shape cast against a few bodies: what a picker, a line of sight or a
//! character sweep asks of the world. `cargo run --example ray_cast`

use rigid::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut world = World::default();
    let sphere = world.add_body(
        BodyDesc::fixed(Shape::sphere(1.0))
            .at(DVec3::new(0.0, 0.0, -5.0))
            .named("sphere"),
    )?;
    world.add_body(
        BodyDesc::fixed(Shape::cuboid(DVec3::new(1.0, 1.0, 1.0)))
            .at(DVec3::new(4.0, 0.0, -5.0))
            .named("box"),
    )?;
    world.add_body(
        BodyDesc::fixed(Shape::capsule(0.5, 1.0))
            .at(DVec3::new(-4.0, 0.0, -5.0))
            .named("capsule"),
    )?;

    let eye = DVec3::ZERO;
    for target in [
        DVec3::new(0.0, 0.0, -5.0),
        DVec3::new(4.0, 0.5, -5.0),
        DVec3::new(-4.0, 1.0, -5.0),
        DVec3::new(0.0, 5.0, -5.0),
    ] {
        match world.ray_cast(eye, target - eye, 100.0)? {
            Some(hit) => println!(
                "ray towards {target}: hits {} at {:.3} m, point {:.3}, normal {:.3}",
                world.body(hit.body).name,
                hit.distance,
                hit.point,
                hit.normal
            ),
            None => println!("ray towards {target}: hits nothing"),
        }
    }

    // A ball of radius 0.5 swept from the eye towards the sphere stops when the surfaces
    // touch: 5 − 1 − 0.5 = 3.5 m along the way.
    let ball = Shape::sphere(0.5);
    let swept = world.shape_cast(&ball, eye, DQuat::IDENTITY, DVec3::NEG_Z, 100.0)?;
    if let Some(hit) = swept {
        assert_eq!(hit.body, sphere);
        println!(
            "a ball of radius 0.5 swept along -z touches the sphere after {:.6} m",
            hit.distance
        );
    }
    Ok(())
}
