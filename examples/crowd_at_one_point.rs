//! Boxes created all at one point, without gravity: prints, for each crowd size, how fast
//! the boxes move once they have parted (median and fastest, against `max_push_out`), how
//! many are still awake (sleeping is on) and the deepest overlap left after 3 s.
//! `cargo run --release --example crowd_at_one_point`

use rigid::prelude::*;

const DT: f64 = 1.0 / 60.0;
const STEPS: usize = 180;

fn main() -> Result<(), AddBodyError> {
    println!(
        "| boxes | median speed, m/s | fastest, m/s | max_push_out, m/s | awake | deepest overlap, m |"
    );
    println!("|---|---|---|---|---|---|");
    for count in [2, 10, 30, 100] {
        let mut world = World::default();
        for _ in 0..count {
            world.add_body(BodyDesc::dynamic(Shape::cuboid(DVec3::splat(0.5))))?;
        }
        for _ in 0..STEPS {
            world.step(DT);
        }
        let mut speeds: Vec<f64> = (world.bodies().iter())
            .map(|body| body.velocity().length())
            .collect();
        speeds.sort_by(f64::total_cmp);
        let awake = world.bodies().iter().filter(|b| !b.sleeping).count();
        println!(
            "| {count} | {:.3} | {:.3} | {} | {awake} | {:.4} |",
            speeds[speeds.len() / 2],
            speeds[speeds.len() - 1],
            world.settings.solver.max_push_out,
            world.max_penetration()
        );
    }
    Ok(())
}
