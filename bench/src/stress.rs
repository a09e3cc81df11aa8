//! Stability stress: long tumbling, tall stacks, heavy-on-light stacks, very fast projectiles
//! and a long pachinko run. Each returns what was measured and whether it passed its stated
//! criterion.

use glam::DVec3;

use crate::worst_drift;
use rigid::physics::{Aabb, BodyDesc, BodyId, EnvironmentForce, Material, Shape, World};
use rigid::scene;

pub struct Outcome {
    pub case: String,
    pub measured: String,
    pub criterion: &'static str,
    pub passed: bool,
}

/// A box spun about a tilted axis for `steps` steps of 1/60 s without gravity or contacts.
pub fn tumbling(steps: usize) -> Outcome {
    let mut world = World::default();
    let id = world
        .add_body(
            BodyDesc::dynamic(Shape::cuboid(DVec3::new(0.1, 0.3, 0.6)))
                .with_angular_velocity(DVec3::new(3.0, 5.0, 1.0)),
        )
        .expect("valid box");
    let (e0, l0) = {
        let b = world.body(id);
        (b.kinetic_energy(), b.angular_momentum)
    };
    for _ in 0..steps {
        world.step(1.0 / 60.0);
    }
    let b = world.body(id);
    let r = b.orientation;
    let error = r.transpose() * r - glam::DMat3::IDENTITY;
    let orthonormality = [error.x_axis, error.y_axis, error.z_axis]
        .iter()
        .map(|c| c.abs().max_element())
        .fold(0.0, f64::max);
    let energy = (b.kinetic_energy() - e0).abs() / e0;
    let momentum = (b.angular_momentum - l0).length() / l0.length();
    Outcome {
        case: format!("tumbling box, {steps} steps of 1/60 s (midpoint)"),
        measured: format!(
            "max |RᵀR − I| {orthonormality:.1e}, |ΔE|/E {energy:.1e}, |ΔL|/|L| {momentum:.1e}"
        ),
        criterion: "|RᵀR − I| < 1e-12, |ΔL|/|L| < 1e-12, |ΔE|/E < 1e-2",
        passed: orthonormality < 1e-12 && momentum < 1e-12 && energy < 1e-2,
    }
}

fn ground(world: &mut World) {
    let floor = BodyDesc::fixed(Shape::cuboid(DVec3::new(20.0, 0.5, 20.0))).at(DVec3::Y * -0.5);
    world.add_body(floor).expect("valid floor");
}

/// `height` unit boxes stacked on the ground, 10 s at 1/60 s with the default soft solver.
pub fn stack(height: usize) -> Outcome {
    let mut world = World::default();
    world.forces.push(EnvironmentForce::earth_gravity());
    ground(&mut world);
    let boxes: Vec<BodyId> = (0..height)
        .map(|i| {
            let at = DVec3::Y * (0.5 + i as f64);
            world
                .add_body(BodyDesc::dynamic(Shape::cuboid(DVec3::splat(0.5))).at(at))
                .expect("valid box")
        })
        .collect();
    let start: Vec<DVec3> = boxes.iter().map(|&b| world.body(b).position).collect();
    for _ in 0..600 {
        world.step(1.0 / 60.0);
    }
    let drift = worst_drift(&world, &boxes, &start);
    let asleep = boxes.iter().filter(|&&b| world.body(b).sleeping).count();
    Outcome {
        case: format!("stack of {height} boxes, 10 s at 1/60 s"),
        measured: format!(
            "worst drift {:.1} mm, {asleep}/{height} asleep",
            drift * 1e3
        ),
        criterion: "drift < 1 cm",
        passed: drift < 0.01,
    }
}

/// A box `ratio` times heavier resting on a unit box, 10 s at 1/60 s with `substeps` (the
/// default 8 and more: at 1:1000 and 8 the pair creeps sideways).
pub fn heavy_on_light(ratio: f64, substeps: u32) -> Outcome {
    let mut world = World::default();
    world.settings.solver.substeps = substeps;
    world.forces.push(EnvironmentForce::earth_gravity());
    ground(&mut world);
    let light = Material::default();
    let heavy = Material {
        density: light.density * ratio,
        ..light
    };
    let cube = || Shape::cuboid(DVec3::splat(0.5));
    let bottom = world
        .add_body(BodyDesc::dynamic(cube()).at(DVec3::Y * 0.5))
        .expect("valid box");
    let top = world
        .add_body(
            BodyDesc::dynamic(cube())
                .at(DVec3::Y * 1.5)
                .with_material(heavy),
        )
        .expect("valid box");
    let start = [world.body(bottom).position, world.body(top).position];
    for _ in 0..600 {
        world.step(1.0 / 60.0);
    }
    let drift = worst_drift(&world, &[bottom, top], &start);
    let asleep = [bottom, top]
        .iter()
        .filter(|&&b| world.body(b).sleeping)
        .count();
    Outcome {
        case: format!(
            "box of mass ratio 1:{ratio} on a unit box, 10 s at 1/60 s, {substeps} substeps"
        ),
        measured: format!("worst drift {:.1} mm, {asleep}/2 asleep", drift * 1e3),
        criterion: "drift < 1 cm",
        passed: drift < 0.01,
    }
}

/// A 5 cm sphere at `speed` m/s straight at a 10 cm static wall, 1 s at 1/60 s.
pub fn projectile(speed: f64) -> Outcome {
    let mut world = World::default();
    let wall = BodyDesc::fixed(Shape::cuboid(DVec3::new(0.05, 2.0, 2.0))).at(DVec3::X * 5.0);
    world.add_body(wall).expect("valid wall");
    let ball = world
        .add_body(BodyDesc::dynamic(Shape::sphere(0.05)).with_velocity(DVec3::X * speed))
        .expect("valid ball");
    let mut furthest: f64 = 0.0;
    for _ in 0..60 {
        world.step(1.0 / 60.0);
        furthest = furthest.max(world.body(ball).position.x);
    }
    Outcome {
        case: format!("5 cm sphere at {speed} m/s into a 10 cm wall"),
        measured: format!("furthest centre x {furthest:.4} m (wall face at 4.95 m)"),
        criterion: "never past the wall face",
        passed: furthest <= 4.95,
    }
}

/// The pachinko scene for `seconds`: balls stay in their box, finite, energy never above
/// the start.
pub fn long_pachinko(seconds: f64) -> Outcome {
    let loaded = scene::load("pachinko").expect("built-in scene");
    let mut world = loaded.build_world().expect("builds");
    let dt = loaded.settings.dt;
    let energy = |w: &World| {
        let t = w.totals();
        t.kinetic_energy + t.potential_energy
    };
    let e0 = energy(&world);
    let mut highest = e0;
    let steps = (seconds / dt).round() as usize;
    for _ in 0..steps {
        world.step(dt);
        highest = highest.max(energy(&world));
    }
    let inside = |b: &Aabb| b.min.x > -0.661 && b.max.x < 0.661 && b.min.y > -0.001;
    let escaped = world
        .bodies()
        .iter()
        .filter(|b| b.is_dynamic() && !inside(&Aabb::of_body(b)))
        .count();
    let faults = world.faults().len();
    let rise = (highest - e0) / e0.abs();
    Outcome {
        case: format!("pachinko, {seconds} s at 1/{:.0} s", 1.0 / dt),
        measured: format!(
            "{escaped} escaped, {faults} non-finite, highest energy {rise:+.1e} of start"
        ),
        criterion: "none escaped or non-finite, energy never above the start",
        passed: escaped == 0 && faults == 0 && rise <= 1e-9,
    }
}
