//! Work-precision of the integrators on the free-body cases:
//! C1 free fall (position error after 1 s) and C3 torque-free spin about the intermediate
//! axis (largest relative kinetic-energy drift over 20 s; angular momentum is exact by form).

use glam::DVec3;

use crate::{DTS, Measurement, median_time};
use rigid::physics::{BodyDesc, EnvironmentForce, Integrator, Shape, World, WorldSettings};

/// A world stepping in one substep: the integrator alone, with no contact solver around it.
fn integrator_world(integrator: Integrator) -> World {
    let mut world = World::new(WorldSettings {
        integrator,
        ..WorldSettings::default()
    });
    world.settings.solver.substeps = 1;
    world
}

const REPEATS: usize = 5;

/// C1: a ball dropped from rest, |y(1 s) − (y0 − g/2)|.
pub fn free_fall(integrator: Integrator, dt: f64) -> Measurement {
    let steps = (1.0 / dt).round() as usize;
    let (error, seconds) = median_time(REPEATS, || {
        let mut world = integrator_world(integrator);
        world.forces.push(EnvironmentForce::earth_gravity());
        let ball = world
            .add_body(BodyDesc::dynamic(Shape::sphere(0.1)).at(DVec3::Y * 10.0))
            .expect("valid body");
        for _ in 0..steps {
            world.step(dt);
        }
        let g = rigid::physics::dynamics::forces::STANDARD_GRAVITY;
        (world.body(ball).position.y - (10.0 - 0.5 * g)).abs()
    });
    Measurement {
        case: "C1 free fall",
        config: integrator.name().into(),
        dt,
        error,
        micros_per_sim_second: seconds * 1e6,
    }
}

/// C3: a box with principal moments ∝ (0.45, 0.37, 0.10) spun at 10 rad/s about its
/// intermediate axis with a 1e-3 perturbation, for 20 s.
pub fn intermediate_axis_spin(integrator: Integrator, dt: f64) -> Measurement {
    const SECONDS: f64 = 20.0;
    let steps = (SECONDS / dt).round() as usize;
    let (error, seconds) = median_time(REPEATS, || {
        let mut world = integrator_world(integrator);
        let block = world
            .add_body(
                BodyDesc::dynamic(Shape::cuboid(DVec3::new(0.1, 0.3, 0.6)))
                    .with_angular_velocity(DVec3::new(0.01, 10.0, 0.01)),
            )
            .expect("valid body");
        let energy0 = world.body(block).kinetic_energy();
        let mut drift: f64 = 0.0;
        for _ in 0..steps {
            world.step(dt);
            drift = drift.max((world.body(block).kinetic_energy() - energy0).abs() / energy0);
        }
        drift
    });
    Measurement {
        case: "C3 spin",
        config: integrator.name().into(),
        dt,
        error,
        micros_per_sim_second: seconds * 1e6 / SECONDS,
    }
}

/// Every integrator at every dt, for one case.
pub fn sweep(case: fn(Integrator, f64) -> Measurement) -> Vec<Measurement> {
    Integrator::ALL
        .iter()
        .flat_map(|&integrator| DTS.iter().map(move |&dt| case(integrator, dt)))
        .collect()
}
