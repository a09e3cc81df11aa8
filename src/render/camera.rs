//! An orbit camera: it circles a target point. Mouse drags orbit and pan, the wheel zooms.

use glam::camera::rh::{proj, view};
use glam::{Mat4, Vec2, Vec3};

use crate::sim::CameraHint;

const FOV_Y: f32 = 45.0 * std::f32::consts::PI / 180.0;
const NEAR: f32 = 0.1;
const FAR: f32 = 500.0;
/// Radians per pixel of mouse motion when orbiting.
const ORBIT_SPEED: f32 = 0.008;
/// Pitch stays short of the poles, where the up vector would flip.
const PITCH_LIMIT: f32 = 1.5;

/// A camera that looks at `target` from `distance` away, placed by two angles. World space
/// is y up; the camera's up is always +y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// The point looked at and orbited around, world space.
    pub target: Vec3,
    /// From the target to the eye, m. [`zoom`](Self::zoom) keeps it within 0.2 to 200.
    pub distance: f32,
    /// Radians around the world y axis, from +z (0 puts the eye on the target's +z side).
    pub yaw: f32,
    /// Radians of elevation above the horizontal plane; [`orbit`](Self::orbit) keeps it
    /// within ±1.5.
    pub pitch: f32,
}

/// A half-line in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts: for a camera ray, on the near plane.
    pub origin: Vec3,
    /// Unit length.
    pub direction: Vec3,
}

impl Ray {
    /// The point `t` along the ray; `direction` is unit length, so `t` is a distance in m.
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.direction * t
    }
}

impl OrbitCamera {
    /// The camera with its eye at `hint.eye` looking at `hint.target`. An eye closer than
    /// 0.1 m to the target is moved out to 0.1 m.
    pub fn from_hint(hint: &CameraHint) -> Self {
        let offset = hint.eye - hint.target;
        let distance = offset.length().max(0.1);
        OrbitCamera {
            target: hint.target,
            distance,
            yaw: offset.x.atan2(offset.z),
            pitch: (offset.y / distance).clamp(-1.0, 1.0).asin(),
        }
    }

    /// The eye position, world space.
    pub fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        self.target + Vec3::new(sy * cp, sp, cy * cp) * self.distance
    }

    /// The view's up direction in world space: unit length, square to the line of sight.
    pub fn up(&self) -> Vec3 {
        self.view().row(1).truncate()
    }

    /// Half the height the view shows at the target's distance, m.
    pub fn half_height_at_target(&self) -> f32 {
        self.distance * (FOV_Y / 2.0).tan()
    }

    /// The world-to-view matrix (right-handed, looking down view -z, +y up).
    pub fn view(&self) -> Mat4 {
        view::look_at_mat4(self.eye(), self.target, Vec3::Y)
    }

    /// The view-to-clip perspective: 45° vertical field of view, near plane 0.1 m, far plane
    /// 500 m, depth from 0 (near) to 1 (far). `aspect` is width over height.
    pub fn projection(&self, aspect: f32) -> Mat4 {
        // WebGPU clip space: z in [0, 1], y up, as in DirectX.
        proj::directx::perspective(FOV_Y, aspect.max(1e-3), NEAR, FAR)
    }

    /// The world-to-clip matrix, [`projection`](Self::projection) times
    /// [`view`](Self::view).
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }

    /// Turns the camera around the target by a mouse motion in pixels: x changes the yaw,
    /// y the pitch.
    pub fn orbit(&mut self, delta: Vec2) {
        self.yaw -= delta.x * ORBIT_SPEED;
        self.pitch = (self.pitch + delta.y * ORBIT_SPEED).clamp(-PITCH_LIMIT, PITCH_LIMIT);
    }

    /// Slides the target in the view plane; `viewport_height` in pixels makes the scene
    /// follow the cursor at the target's depth.
    pub fn pan(&mut self, delta: Vec2, viewport_height: f32) {
        let view = self.view();
        let right = view.row(0).truncate();
        let up = view.row(1).truncate();
        let per_pixel = 2.0 * self.distance * (FOV_Y / 2.0).tan() / viewport_height.max(1.0);
        self.target += (-right * delta.x + up * delta.y) * per_pixel;
    }

    /// Moves closer (positive `steps`) or farther, by 10 % per step.
    pub fn zoom(&mut self, steps: f32) {
        self.distance = (self.distance * 0.9f32.powf(steps)).clamp(0.2, 200.0);
    }

    /// The ray through a pixel (`pixel` from the top-left of a viewport of `size` pixels).
    pub fn ray(&self, pixel: Vec2, size: Vec2) -> Ray {
        let ndc = Vec2::new(2.0 * pixel.x / size.x - 1.0, 1.0 - 2.0 * pixel.y / size.y);
        let inverse = self.view_projection(size.x / size.y).inverse();
        let near = inverse.project_point3(ndc.extend(0.0));
        let far = inverse.project_point3(ndc.extend(1.0));
        Ray {
            origin: near,
            direction: (far - near).normalize(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hint_round_trips_to_the_same_eye() {
        let hint = CameraHint {
            eye: Vec3::new(5.0, 4.0, 7.0),
            target: Vec3::new(0.0, 1.0, 0.0),
            follow: None,
        };
        let camera = OrbitCamera::from_hint(&hint);
        assert!(camera.eye().distance(hint.eye) < 1e-4);
    }

    /// Whether `point` projects inside a 16:9 view of `camera`.
    fn in_view(camera: &OrbitCamera, point: Vec3) -> bool {
        let clip = camera.view_projection(16.0 / 9.0) * point.extend(1.0);
        let ndc = clip.truncate() / clip.w;
        clip.w > 0.0 && ndc.x.abs() < 1.0 && ndc.y.abs() < 1.0
    }

    /// The car scene's camera follows its chassis (`camera.follow`): after 12 s, with the
    /// car stopped at the wall 29 m on, past the hill and the crates, the chassis is in view
    /// from the moved camera, and not from the scene's fixed one.
    #[test]
    fn the_car_scene_keeps_its_chassis_in_view() {
        let mut sim = crate::sim::Simulation::new("car").unwrap();
        while sim.ticks() as f64 * sim.settings().dt < 12.0 {
            sim.step();
        }
        let snapshot = sim.snapshot(web_time::Instant::now());
        let poses: Vec<_> = snapshot.bodies.iter().map(|b| b.pose).collect();
        let chassis = snapshot.names.iter().position(|n| n == "chassis").unwrap();
        let at = poses[chassis].position;
        assert!(at.x > 20.0, "the car drove on: {at}");
        let fixed = OrbitCamera::from_hint(&snapshot.camera);
        let mut moved = fixed;
        moved.target += snapshot.camera.follow_shift(&poses);
        assert!(!in_view(&fixed, at), "{at}");
        assert!(in_view(&moved, at), "{at}");
    }

    #[test]
    fn centre_ray_points_at_the_target() {
        let camera = OrbitCamera::from_hint(&CameraHint {
            eye: Vec3::new(0.0, 3.0, 8.0),
            target: Vec3::ZERO,
            follow: None,
        });
        let ray = camera.ray(Vec2::new(400.0, 300.0), Vec2::new(800.0, 600.0));
        let to_target = (camera.target - ray.origin).normalize();
        assert!(ray.direction.dot(to_target) > 0.9999);
    }
}
