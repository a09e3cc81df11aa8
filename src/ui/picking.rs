//! Which body is under the cursor: the engine's exact ray cast (`ray_cast_shape`) against the
//! bodies drawn at their interpolated poses, after a cheap test against their bounds (box and
//! sphere) throws out most of them.

use glam::{DMat3, DQuat, Vec3};

use crate::physics::PosedShape;
use crate::physics::ray_cast_shape;
use crate::render::Ray;
use crate::sim::Snapshot;
use crate::sim::snapshot::BodyPose;

/// How far a pick reaches, m.
const PICK_RANGE: f64 = 1e4;

/// A body hit by a ray, and where.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pick {
    /// Index into the snapshot's bodies.
    pub body: usize,
    /// Where the ray meets the body's surface, world space.
    pub point: Vec3,
    /// The surface's unit normal at `point`, facing the ray.
    pub normal: Vec3,
    /// Distance along the ray to `point`, m.
    pub distance: f32,
}

/// The nearest visible body the ray hits within 10 km, with bodies drawn at `poses` (one
/// per body of `snapshot`).
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
            if enter > aabb.1.min(sphere.1) {
                return None;
            }
            let shape = snapshot.shapes.shapes.get(body.shape_id as usize)?;
            let rotation =
                DMat3::from_quat(DQuat::from_array(pose.rotation.to_array().map(f64::from)));
            let posed = PosedShape::new(shape, pose.position.as_dvec3(), rotation);
            let direction = ray.direction.as_dvec3().normalize();
            let hit = ray_cast_shape(&posed, ray.origin.as_dvec3(), direction, PICK_RANGE)?;
            Some(Pick {
                body: index,
                point: hit.point.as_vec3(),
                normal: hit.normal.as_vec3(),
                distance: hit.distance as f32,
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
pub(crate) mod tests {
    use super::*;
    use crate::sim::Simulation;
    use std::time::Instant;

    /// The built-in scene `name` as loaded, and its bodies' poses.
    pub(crate) fn scene_at_start(name: &str) -> (Snapshot, Vec<BodyPose>) {
        let snapshot = Simulation::new(name).unwrap().snapshot(Instant::now());
        let poses = snapshot.bodies.iter().map(|b| b.pose).collect();
        (snapshot, poses)
    }

    #[test]
    fn picks_the_nearest_body_along_the_ray() {
        // falling_box: platform (0) ±1.5 m with its top at y 0, cube (1) ±0.5 m, box (2) at
        // y 4.5.
        let (snapshot, poses) = scene_at_start("falling_box");
        let down = |x: f32, z: f32| Ray {
            origin: Vec3::new(x, 10.0, z),
            direction: -Vec3::Y,
        };
        assert_eq!(pick(&down(0.35, 0.2), &snapshot, &poses).unwrap().body, 2);
        // Near the cube's corner the ray meets its top face (y = 1) exactly, not its bounding
        // sphere (which it enters at y ≈ 1.087).
        let corner = pick(&down(-0.45, -0.45), &snapshot, &poses).unwrap();
        assert_eq!(corner.body, 1);
        assert!((corner.point.y - 1.0).abs() < 1e-4, "{}", corner.point);
        let hit = pick(&down(1.2, 1.2), &snapshot, &poses).unwrap();
        assert_eq!(hit.body, 0);
        assert!((hit.point.y - 0.0).abs() < 1e-4);
        assert!(pick(&down(9.0, 0.0), &snapshot, &poses).is_none());
    }
}
