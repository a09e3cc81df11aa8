//! Bodies the panel spawns, and where they go: at the requested point if it is free, else on
//! top of whatever occupies that spot. Spawned bodies never start inside one another, so a
//! storm of spawns at one point becomes a falling column instead of thousands of bodies
//! overlapping in one place (n² contact pairs and an explosion).

use glam::{DMat3, DQuat, DVec3};

use crate::physics::{Aabb, BodyDesc, Material, Shape, World};
use crate::sim::command::SpawnKind;

/// Vertical clearance left between a spawned body and the one below it, m.
const SPAWN_GAP: f64 = 0.02;

/// A body of `kind`, with a small tilt and spin so that it does not land perfectly flat.
/// `seed` picks the random hull's points.
pub fn body(kind: SpawnKind, seed: u64, material: Material) -> BodyDesc {
    BodyDesc::dynamic(shape(kind, seed))
        .named(kind.name())
        .rotated(DQuat::from_rotation_z(0.3) * DQuat::from_rotation_x(0.2))
        .with_angular_velocity(DVec3::new(0.5, 1.0, 0.0))
        .with_material(material)
}

/// The bounding boxes of the bodies as they are now, for `free_spot`.
pub fn body_boxes(world: &World) -> Vec<Aabb> {
    world.bodies().iter().map(Aabb::of_body).collect()
}

/// The bounding box `desc` has when placed at `position`.
pub fn box_at(desc: &BodyDesc, position: DVec3) -> Aabb {
    Aabb::of_shape(&desc.shape, position, DMat3::from_quat(desc.rotation))
}

/// Where `desc` goes when asked for at `position`: there if its bounding box touches none of
/// `boxes`, otherwise just above the highest box over the same footprint. One pass over the
/// boxes, so a spawn costs O(n) however crowded the spot is.
pub fn free_spot(boxes: &[Aabb], desc: &BodyDesc, position: DVec3) -> DVec3 {
    let wanted = box_at(desc, position);
    let mut overlapped = false;
    let mut top = f64::NEG_INFINITY;
    for other in boxes {
        let same_footprint = other.min.x <= wanted.max.x
            && other.max.x >= wanted.min.x
            && other.min.z <= wanted.max.z
            && other.max.z >= wanted.min.z;
        if same_footprint && other.max.y >= wanted.min.y {
            overlapped |= other.overlaps(&wanted);
            top = top.max(other.max.y);
        }
    }
    if !overlapped {
        return position;
    }
    position + DVec3::Y * (top + SPAWN_GAP - wanted.min.y)
}

fn shape(kind: SpawnKind, seed: u64) -> Shape {
    match kind {
        SpawnKind::Sphere => Shape::sphere(0.3),
        SpawnKind::Box => Shape::cuboid(DVec3::splat(0.3)),
        SpawnKind::Capsule => Shape::capsule(0.3, 0.2),
        SpawnKind::Cylinder => Shape::cylinder(0.25, 0.3),
        SpawnKind::Hull => random_hull(seed),
    }
}

/// The hull of 14 points at random directions and radii 0.2 to 0.35 m. Points spread over a
/// sphere never all lie in one plane, so the hull always exists.
fn random_hull(seed: u64) -> Shape {
    let mut state = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    let mut next = move || {
        // A 64-bit linear congruential generator; the top 53 bits give a uniform [0, 1).
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let points: Vec<DVec3> = (0..14)
        .map(|_| {
            let z = 2.0 * next() - 1.0;
            let angle = std::f64::consts::TAU * next();
            let ring = (1.0 - z * z).sqrt();
            DVec3::new(ring * angle.cos(), z, ring * angle.sin()) * (0.2 + 0.15 * next())
        })
        .collect();
    Shape::hull(&points).unwrap_or(Shape::sphere(0.3))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::BodyDesc;

    fn world_with_floor() -> World {
        let mut world = World::default();
        let floor = BodyDesc::fixed(Shape::cuboid(DVec3::new(5.0, 0.5, 5.0)));
        world.add_body(floor).unwrap();
        world
    }

    #[test]
    fn a_free_spot_is_kept_and_a_taken_one_is_raised_above_its_occupant() {
        let world = world_with_floor();
        let boxes = body_boxes(&world);
        let ball = body(SpawnKind::Sphere, 0, Material::default());
        let free = DVec3::new(1.0, 3.0, 0.0);
        assert_eq!(free_spot(&boxes, &ball, free), free);
        // Asked for inside the floor (top at y = 0.5): raised to rest SPAWN_GAP above it.
        let spot = free_spot(&boxes, &ball, DVec3::new(1.0, 0.2, -2.0));
        assert_eq!((spot.x, spot.z), (1.0, -2.0));
        assert!((box_at(&ball, spot).min.y - (0.5 + SPAWN_GAP)).abs() < 1e-12);
        // Beside the floor's footprint nothing is in the way.
        let beside = DVec3::new(7.0, 0.2, 0.0);
        assert_eq!(free_spot(&boxes, &ball, beside), beside);
    }
}
