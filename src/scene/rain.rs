//! A rain of mixed bodies (spheres, boxes, capsules, cylinders in turn) into an open bin sized
//! to hold them, at any count: the benchmarks' scaling workload and the determinism tests'. Bodies start on a grid 10 layers deep, 0.6 m apart, so
//! nothing overlaps at the start and the bin fills to about the same depth at any count.

use glam::{DQuat, DVec3};

use crate::physics::{BodyDesc, BroadPhaseKind, EnvironmentForce, Shape, World, WorldSettings};

const LAYERS: usize = 10;
const SPACING: f64 = 0.6;

/// `count` bodies over a bin, with the given broad phase and otherwise default settings.
pub fn rain_world(count: usize, broad_phase: BroadPhaseKind) -> World {
    let mut world = World::new(WorldSettings {
        broad_phase,
        ..WorldSettings::default()
    });
    world.forces.push(EnvironmentForce::earth_gravity());
    let per_layer = count.div_ceil(LAYERS);
    let side = (per_layer as f64).sqrt().ceil() as usize;
    let half = 0.5 * side as f64 * SPACING + 0.3;
    add_bin(&mut world, half);
    for i in 0..count {
        let layer = i / per_layer;
        let k = i % per_layer;
        let at = DVec3::new(
            (k % side) as f64 * SPACING - half + 0.6,
            1.0 + layer as f64 * SPACING,
            (k / side) as f64 * SPACING - half + 0.6,
        );
        let tilt = DQuat::from_euler(glam::EulerRot::XYZ, 0.3 * i as f64, 0.7 * i as f64, 0.0);
        let body = BodyDesc::dynamic(shape(i)).at(at).rotated(tilt);
        world.add_body(body).expect("valid rain body");
    }
    world
}

fn shape(i: usize) -> Shape {
    match i % 4 {
        0 => Shape::sphere(0.15),
        1 => Shape::cuboid(DVec3::new(0.15, 0.1, 0.12)),
        2 => Shape::capsule(0.12, 0.08),
        _ => Shape::cylinder(0.08, 0.15),
    }
}

/// A floor with its top at y = 0 and four walls 3 m high around a square of half-size `half`.
fn add_bin(world: &mut World, half: f64) {
    let wall = 0.1;
    let pieces = [
        (
            DVec3::new(half + wall, wall, half + wall),
            DVec3::new(0.0, -wall, 0.0),
        ),
        (
            DVec3::new(wall, 1.5, half),
            DVec3::new(-half - wall, 1.5, 0.0),
        ),
        (
            DVec3::new(wall, 1.5, half),
            DVec3::new(half + wall, 1.5, 0.0),
        ),
        (
            DVec3::new(half, 1.5, wall),
            DVec3::new(0.0, 1.5, -half - wall),
        ),
        (
            DVec3::new(half, 1.5, wall),
            DVec3::new(0.0, 1.5, half + wall),
        ),
    ];
    for (half_extents, at) in pieces {
        let piece = BodyDesc::fixed(Shape::cuboid(half_extents)).at(at);
        world.add_body(piece).expect("valid bin");
    }
}
