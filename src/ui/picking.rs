//! Which body is under the cursor. Until the engine has a ray-cast query, a body is hit where
//! the ray enters both its bounding box and its bounding sphere (the intersection of two
//! convex bounds, tight enough for boxes, balls and pins). Swap `pick` for the engine's
//! query when it exists.

use glam::Vec3;

use crate::render::Ray;
use crate::sim::Snapshot;
use crate::sim::snapshot::BodyPose;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pick {
    pub body: usize,
    /// Where the ray enters the body's bounds, world space.
    pub point: Vec3,
    /// Distance along the ray to `point`.
    pub distance: f32,
}

/// The nearest body the ray hits, with bodies drawn at `poses`.
pub fn pick(ray: &Ray, snapshot: &Snapshot, poses: &[BodyPose]) -> Option<Pick> {
    snapshot
        .bodies
        .iter()
        .zip(poses)
        .enumerate()
        .filter(|(_, (body, _))| body.visible)
        .filter_map(|(index, (body, pose))| {
            let shift = pose.position - body.pose.position;
            let aabb = ray_box(ray, body.aabb.0 + shift, body.aabb.1 + shift)?;
            let sphere = ray_sphere(ray, pose.position, body.bounding_radius)?;
            let enter = aabb.0.max(sphere.0).max(0.0);
            let exit = aabb.1.min(sphere.1);
            (enter <= exit).then(|| Pick {
                body: index,
                point: ray.at(enter),
                distance: enter,
            })
        })
        .min_by(|a, b| a.distance.total_cmp(&b.distance))
}

/// Entry and exit distances of a ray through an axis-aligned box (slab method).
fn ray_box(ray: &Ray, min: Vec3, max: Vec3) -> Option<(f32, f32)> {
    let inverse = ray.direction.recip();
    let a = (min - ray.origin) * inverse;
    let b = (max - ray.origin) * inverse;
    let enter = a.min(b).max_element();
    let exit = a.max(b).min_element();
    (enter <= exit && exit >= 0.0).then_some((enter, exit))
}

fn ray_sphere(ray: &Ray, centre: Vec3, radius: f32) -> Option<(f32, f32)> {
    let to_centre = centre - ray.origin;
    let along = to_centre.dot(ray.direction);
    let miss_sq = to_centre.length_squared() - along * along;
    let half_chord_sq = radius * radius - miss_sq;
    if half_chord_sq < 0.0 {
        return None;
    }
    let half_chord = half_chord_sq.sqrt();
    (along + half_chord >= 0.0).then_some((along - half_chord, along + half_chord))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::Simulation;
    use std::time::Instant;

    #[test]
    fn picks_the_nearest_body_along_the_ray() {
        // falling_box: platform (0) ±2.5 m with its top at y 0, cube (1) ±0.5 m, box (2) at y 4.
        let snapshot = Simulation::new("falling_box")
            .unwrap()
            .snapshot(Instant::now());
        let poses: Vec<_> = snapshot.bodies.iter().map(|b| b.pose).collect();
        let down = |x: f32, z: f32| Ray {
            origin: Vec3::new(x, 10.0, z),
            direction: -Vec3::Y,
        };
        assert_eq!(pick(&down(0.35, 0.2), &snapshot, &poses).unwrap().body, 2);
        assert_eq!(
            pick(&down(-0.45, -0.45), &snapshot, &poses).unwrap().body,
            1
        );
        let hit = pick(&down(2.0, 2.0), &snapshot, &poses).unwrap();
        assert_eq!(hit.body, 0);
        assert!((hit.point.y - 0.0).abs() < 1e-4);
        assert!(pick(&down(9.0, 0.0), &snapshot, &poses).is_none());
    }
}
