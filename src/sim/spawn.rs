//! Bodies the panel spawns, and where they go. The viewer aims a spawn where the user looks
//! (`off_surface`: just off the surface under the cursor or the view's centre) and sends
//! that point in the command, so a replay never needs the camera; the simulation then puts
//! the body there if it is free, else on top of whatever occupies that spot (`free_spot`).
//! Spawned bodies never start inside one another, so a storm of spawns at one point becomes
//! a falling column instead of thousands of bodies overlapping in one place (n² contact pairs
//! and an explosion).

use glam::{DMat3, DQuat, DVec3};

use crate::physics::{Aabb, BodyDesc, Material, Shape, World};
use crate::sim::command::SpawnKind;

/// Vertical clearance left between a spawned body and the one below it, m; also between a
/// body spawned off a surface and that surface.
const SPAWN_GAP: f64 = 0.02;

/// The random hull's points lie this far from its origin, m (least, most).
const HULL_RADII: (f64, f64) = (0.2, 0.35);

/// A point of the scene's surface the user aimed at, with the surface's unit normal there,
/// facing the viewer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    /// World coordinates, m.
    pub point: DVec3,
    /// Unit length, pointing out of the surface toward the ray's origin.
    pub normal: DVec3,
}

/// Where a body of `kind` aimed at `hit` goes: out of the surface along its normal by the
/// body's bounding radius plus `SPAWN_GAP`, so that it never starts inside what it was aimed
/// at: above a floor, in front of a wall.
pub fn off_surface(kind: SpawnKind, hit: SurfaceHit) -> DVec3 {
    hit.point + hit.normal * (bounding_radius(kind) + SPAWN_GAP)
}

/// The radius of a sphere about the shape's origin that holds every body of `kind`, m.
pub fn bounding_radius(kind: SpawnKind) -> f64 {
    match kind {
        SpawnKind::Hull => HULL_RADII.1,
        _ => shape(kind, 0).bounding_radius(),
    }
}

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

/// The hull of 14 points at random directions and radii `HULL_RADII`. Points spread over a
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
            let radius = HULL_RADII.0 + (HULL_RADII.1 - HULL_RADII.0) * next();
            DVec3::new(ring * angle.cos(), z, ring * angle.sin()) * radius
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

    #[test]
    fn a_spawn_aimed_at_a_surface_starts_just_off_it() {
        let world = world_with_floor();
        let boxes = body_boxes(&world);
        for kind in SpawnKind::ALL {
            // The floor's top face, hit at (1, 0.5, -2): the body rests its radius above it.
            let floor = SurfaceHit {
                point: DVec3::new(1.0, 0.5, -2.0),
                normal: DVec3::Y,
            };
            let spot = off_surface(kind, floor);
            let radius = bounding_radius(kind);
            assert_eq!((spot.x, spot.z), (1.0, -2.0));
            assert!((spot.y - (0.5 + radius + SPAWN_GAP)).abs() < 1e-12);
            // Free there, so the simulation keeps it, whatever the seed of a hull.
            for seed in 0..8 {
                let desc = body(kind, seed, Material::default());
                assert!(desc.shape.bounding_radius() <= radius + 1e-12);
                assert_eq!(free_spot(&boxes, &desc, spot), spot, "{kind:?}");
            }
            // The floor's side face, seen from +x: the body starts beside it, at the hit's
            // height, not lifted to the floor's top.
            let side = SurfaceHit {
                point: DVec3::new(5.0, 0.0, 1.0),
                normal: DVec3::X,
            };
            let beside = off_surface(kind, side);
            assert_eq!((beside.y, beside.z), (0.0, 1.0));
            assert!(beside.x > 5.0 + radius);
        }
    }
}
