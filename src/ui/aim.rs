//! Where the viewer puts a spawned body: where the user is looking. A spawn aimed along a ray
//! (through the cursor, or through `VIEW_AIM` for the panel's buttons) starts just off the
//! first visible surface the ray meets; a ray that meets nothing puts it above the camera's
//! target, in view. The command carries the point, so a replay never needs the
//! camera.

use glam::{DVec3, Vec2};

use crate::render::{OrbitCamera, Ray};
use crate::sim::snapshot::BodyPose;
use crate::sim::spawn::{self, SurfaceHit};
use crate::sim::{Snapshot, SpawnKind};
use crate::ui::picking;

/// Where in the view the panel's spawns aim, as fractions of its width and height from the
/// top-left: a quarter of the height above the middle, so that the body appears above the
/// scene's centre, not in front of it, and is seen falling.
pub const VIEW_AIM: Vec2 = Vec2::new(0.5, 0.25);

/// How high above the target, as a fraction of the view's half-height there, a spawn aimed
/// at nothing appears: at the height of `VIEW_AIM`.
const MISS_LIFT: f32 = 0.5;

/// Where a body of `kind` aimed along `ray` goes, with the bodies drawn at `poses`: just off
/// the surface the ray meets first (`spawn::off_surface`), or `in_view` when it meets none.
pub fn spawn_position(
    kind: SpawnKind,
    ray: &Ray,
    camera: &OrbitCamera,
    snapshot: &Snapshot,
    poses: &[BodyPose],
) -> DVec3 {
    match picking::pick(ray, snapshot, poses) {
        Some(hit) => spawn::off_surface(
            kind,
            SurfaceHit {
                point: hit.point.as_dvec3(),
                normal: hit.normal.as_dvec3(),
            },
        ),
        None => in_view(camera),
    }
}

/// A point above the camera's target, in the plane through it square to the line of sight:
/// whatever the camera's angle, it lies on screen.
pub fn in_view(camera: &OrbitCamera) -> DVec3 {
    let lift = MISS_LIFT * camera.half_height_at_target();
    (camera.target + camera.up() * lift).as_dvec3()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::CameraHint;
    use crate::ui::picking::tests::scene_at_start;
    use glam::{Vec2, Vec3};

    const VIEW: Vec2 = Vec2::new(990.0, 720.0);

    fn on_screen(camera: &OrbitCamera, point: DVec3) -> bool {
        let clip = camera.view_projection(VIEW.x / VIEW.y) * point.as_vec3().extend(1.0);
        let ndc = clip.truncate() / clip.w;
        clip.w > 0.0 && ndc.x.abs() < 1.0 && ndc.y.abs() < 1.0
    }

    #[test]
    fn a_ray_that_hits_the_scene_spawns_just_above_the_hit() {
        // falling_box: the platform's top face is y = 0, ±1.5 m; the cube (±0.5 m) stands at
        // the origin.
        let (snapshot, poses) = scene_at_start("falling_box");
        let camera = OrbitCamera::from_hint(&snapshot.camera);
        let ray = Ray {
            origin: Vec3::new(1.1, 5.0, 1.2),
            direction: -Vec3::Y,
        };
        let spot = spawn_position(SpawnKind::Box, &ray, &camera, &snapshot, &poses);
        let radius = spawn::bounding_radius(SpawnKind::Box);
        assert!((spot.x - 1.1).abs() < 1e-6 && (spot.z - 1.2).abs() < 1e-6);
        assert!((spot.y - (radius + 0.02)).abs() < 1e-4, "{spot}");
        assert!(on_screen(&camera, spot));
    }

    #[test]
    fn a_ray_that_hits_nothing_spawns_in_view_above_the_target() {
        let (snapshot, poses) = scene_at_start("falling_box");
        for (eye, target) in [
            (Vec3::new(0.0, 3.0, 8.0), Vec3::new(0.0, 30.0, 0.0)),
            (Vec3::new(40.0, 90.0, -5.0), Vec3::new(20.0, 60.0, 10.0)),
        ] {
            let camera = OrbitCamera::from_hint(&CameraHint {
                eye,
                target,
                follow: None,
            });
            let aim = camera.ray(VIEW * VIEW_AIM, VIEW);
            let spot = spawn_position(SpawnKind::Sphere, &aim, &camera, &snapshot, &poses);
            assert!(picking::pick(&aim, &snapshot, &poses).is_none());
            assert!(on_screen(&camera, spot), "{spot} off screen");
            assert!(spot.y > target.y as f64, "{spot} not above the target");
        }
    }
}
