//! Thin rods of square section dropped tilted onto a floor: prints, for each rod and tilt,
//! the highest total energy over 20 s relative to the start (a landing should never exceed
//! 1), the fastest spin, and the centre height and speed at the end.
//! `cargo run --release --example thin_rod` (rods 1 mm × 10 m, 1 mm × 1 m, 4 mm × 1 m and
//! 1 mm × 0.1 m).

use rigid::prelude::*;

const DT: f64 = 1.0 / 60.0;
const STEPS: usize = 1200;

fn main() -> Result<(), AddBodyError> {
    println!(
        "| rod | tilt | energy peak / start | fastest spin, rad/s | centre at end, m | speed at end, m/s |"
    );
    println!("|---|---|---|---|---|---|");
    for (thickness, length) in [(0.001, 10.0), (0.001, 1.0), (0.004, 1.0), (0.001, 0.1)] {
        for tilt in [30.0, 60.0, 85.0] {
            let mut world = World::default();
            world.forces.push(EnvironmentForce::earth_gravity());
            world.add_body(
                BodyDesc::fixed(Shape::cuboid(DVec3::new(20.0, 0.1, 20.0))).at(DVec3::NEG_Y * 0.1),
            )?;
            let turn =
                DQuat::from_rotation_z(0.1745) * DQuat::from_rotation_x(f64::to_radians(tilt));
            let rod = world.add_body(
                BodyDesc::dynamic(Shape::cuboid(
                    DVec3::new(thickness, length, thickness) * 0.5,
                ))
                .at(DVec3::Y * (0.5 * length + 0.1))
                .rotated(turn),
            )?;
            let energy = |w: &World| {
                let totals = w.totals();
                totals.kinetic_energy + totals.potential_energy
            };
            let start = energy(&world);
            let (mut peak, mut spin) = (start, 0.0f64);
            for _ in 0..STEPS {
                world.step(DT);
                peak = peak.max(energy(&world));
                spin = spin.max(world.body(rod).angular_velocity().length());
            }
            let body = world.body(rod);
            println!(
                "| {} mm × {length} m | {tilt}° | {:.4} | {spin:.3e} | {:.5} | {:.2e} |",
                thickness * 1e3,
                peak / start,
                body.position.y,
                body.velocity().length()
            );
        }
    }
    Ok(())
}
