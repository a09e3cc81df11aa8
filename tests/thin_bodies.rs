//! Thin rods dropped onto a floor: however thin a box the validator accepts, a landing never
//! gains energy and the rod comes to rest lying down (the inertia floor,
//! `rigid::physics::dynamics::body::MIN_INERTIA_RATIO`, and the soft step's limit on how
//! far a body in contact turns in a substep).

use glam::{DQuat, DVec3};
use rigid::physics::{BodyDesc, EnvironmentForce, Shape, World};

const DT: f64 = 1.0 / 60.0;

/// A rod of square section `thickness` and `length` dropped from rest with its centre at
/// `length / 2 + 0.1` m, tilted by `tilt` degrees about x then 10° about z, onto a static
/// floor, both of the default material. Returns the largest total energy seen over `seconds` over the energy at the start
/// (zero at the floor's top), and the rod's centre height and speed at the end.
fn drop_rod(thickness: f64, length: f64, tilt: f64, seconds: f64) -> (f64, f64, f64) {
    let mut world = World::default();
    world.forces.push(EnvironmentForce::earth_gravity());
    let floor =
        BodyDesc::fixed(Shape::cuboid(DVec3::new(20.0, 0.1, 20.0))).at(DVec3::new(0.0, -0.1, 0.0));
    world.add_body(floor).expect("valid floor");
    let half = DVec3::new(0.5 * thickness, 0.5 * length, 0.5 * thickness);
    let rod = BodyDesc::dynamic(Shape::cuboid(half))
        .at(DVec3::new(0.0, 0.5 * length + 0.1, 0.0))
        .rotated(
            DQuat::from_rotation_z(10f64.to_radians()) * DQuat::from_rotation_x(tilt.to_radians()),
        );
    let id = world.add_body(rod).expect("valid rod");
    let energy = |world: &World| {
        let totals = world.totals();
        totals.kinetic_energy + totals.potential_energy
    };
    let start = energy(&world);
    let mut highest = start;
    for _ in 0..(seconds / DT).round() as usize {
        world.step(DT);
        highest = highest.max(energy(&world));
    }
    let body = world.body(id);
    (highest / start, body.position.y, body.velocity().length())
}

#[test]
fn thin_rods_never_gain_energy_and_come_to_rest_lying_down() {
    // Before either guard, 1 mm × 10 m spun up to about 6e5 rad/s and left the floor at
    // 83 m/s; with the inertia floor alone, 1 mm × 0.1 m still gained half its energy.
    for (thickness, length) in [(0.001, 10.0), (0.001, 1.0), (0.004, 1.0), (0.001, 0.1)] {
        for tilt in [30.0, 60.0, 85.0] {
            let (peak, height, speed) = drop_rod(thickness, length, tilt, 20.0);
            let case = format!("{thickness} × {length} m at {tilt}°");
            // The energy at the start is all potential; contacts may only take it away.
            // 1e-9: round-off of the sums.
            assert!(
                peak <= 1.0 + 1e-9,
                "{case}: energy peaked at {peak} of the start"
            );
            // Lying down: the centre within the soft contacts' few-mm sink of half the
            // thickness above the floor, and still.
            assert!(
                height < 0.5 * thickness + 0.005 && height > -0.005,
                "{case}: centre at {height} m"
            );
            assert!(speed < 1e-3, "{case}: still moving at {speed} m/s");
        }
    }
}
