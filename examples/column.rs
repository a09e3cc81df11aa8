//! A column of unit boxes standing on a floor, sleeping off: prints, every 100 steps, how
//! far its top box has moved sideways and down. A column taller than the soft contacts can
//! hold leans further at every print. `cargo run --release --example column -- BOXES
//! SUBSTEPS STEPS` (defaults: 25 boxes, the default substeps, 600 steps).

use rigid::prelude::*;

const HALF: f64 = 0.5;
const DENSITY: f64 = 100.0;

fn main() -> Result<(), AddBodyError> {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let boxes = args.first().copied().unwrap_or(25).max(1);
    let mut world = World::default();
    if let Some(&substeps) = args.get(1) {
        world.settings.solver.substeps = substeps.clamp(1, 64) as u32;
    }
    let steps = args.get(2).copied().unwrap_or(600);
    if let Some(&hz) = args.get(3) {
        world.settings.solver.contact_hertz = hz as f64;
    }
    world.settings.sleep.enabled = false;
    world.forces.push(EnvironmentForce::earth_gravity());
    let material = Material {
        density: DENSITY,
        restitution: 0.0,
        friction: 0.6,
    };
    let floor = Shape::cuboid(DVec3::new(50.0, 1.0, 50.0));
    world.add_body(BodyDesc::fixed(floor).at(DVec3::new(0.0, -1.0, 0.0)))?;
    let mut top = None;
    for k in 0..boxes {
        let centre = DVec3::new(0.0, HALF * (2 * k + 1) as f64, 0.0);
        let desc = BodyDesc::dynamic(Shape::cuboid(DVec3::splat(HALF)))
            .at(centre)
            .with_material(material);
        top = Some((world.add_body(desc)?, centre));
    }
    let (top, start) = top.expect("at least one box");
    println!(
        "{boxes} boxes, {} substeps: the top box's displacement (mm)",
        world.settings.solver.substeps
    );
    for step in 1..=steps {
        world.step(1.0 / 60.0);
        if step % 100 == 0 {
            let moved = world.body(top).position - start;
            println!(
                "step {step:5}: sideways {:9.2}, down {:8.2}",
                moved.with_y(0.0).length() * 1e3,
                -moved.y * 1e3
            );
        }
    }
    Ok(())
}
