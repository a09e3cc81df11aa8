//! Pushing a body with the mouse: a point of the body is pulled toward the point under the
//! cursor by a damped spring, applied as one impulse per frame.

use glam::Vec3;

use crate::render::Ray;
use crate::sim::snapshot::BodyPose;
use crate::sim::{BodyState, Command, LineSegment};
use crate::ui::picking::Pick;

/// Spring stiffness per unit mass (1/s²) and its critical damping (1/s).
const STIFFNESS: f32 = 60.0;
const DAMPING: f32 = 15.5;
/// Longest frame the spring integrates over: a stalled frame must not fling the body.
const MAX_FRAME: f32 = 1.0 / 20.0;
const SPRING_COLOR: [f32; 3] = [1.0, 1.0, 1.0];

/// A body held by the mouse: the grabbed point follows the cursor at the depth it was
/// grabbed at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drag {
    /// Index into the snapshot's bodies.
    pub body: usize,
    /// The grabbed point in the body's own frame.
    local_anchor: Vec3,
    /// Distance from the eye at which the cursor point is taken.
    depth: f32,
}

impl Drag {
    /// Grabs the picked point of `pick.body`, drawn at `pose`.
    pub fn start(pick: &Pick, pose: &BodyPose) -> Drag {
        Drag {
            body: pick.body,
            local_anchor: pose.rotation.inverse() * (pick.point - pose.position),
            depth: pick.distance,
        }
    }

    /// The grabbed point, where the body is drawn now.
    pub fn anchor(&self, pose: &BodyPose) -> Vec3 {
        pose.position + pose.rotation * self.local_anchor
    }

    /// The impulse command for a frame of `dt` seconds with the cursor along `ray`, or None
    /// when the body cannot be pushed.
    pub fn push(&self, ray: &Ray, body: &BodyState, pose: &BodyPose, dt: f32) -> Option<Command> {
        if !body.is_dynamic || body.mass <= 0.0 {
            return None;
        }
        let anchor = self.anchor(pose);
        let target = ray.at(self.depth);
        let anchor_velocity =
            body.velocity + body.angular_velocity.cross(anchor - body.center_of_mass);
        let acceleration = STIFFNESS * (target - anchor) - DAMPING * anchor_velocity;
        let impulse = acceleration * body.mass * dt.min(MAX_FRAME);
        Some(Command::ApplyImpulse {
            body: self.body,
            impulse: impulse.as_dvec3(),
            point: anchor.as_dvec3(),
        })
    }

    /// The spring drawn from the body to the cursor.
    pub fn line(&self, ray: &Ray, pose: &BodyPose) -> LineSegment {
        LineSegment {
            from: self.anchor(pose),
            to: ray.at(self.depth),
            color: SPRING_COLOR,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec3, Quat};

    #[test]
    fn pulls_toward_the_cursor_in_proportion_to_mass() {
        let pose = BodyPose {
            position: Vec3::ZERO,
            rotation: Quat::IDENTITY,
        };
        let pick = Pick {
            body: 3,
            point: Vec3::new(0.0, 0.0, 1.0),
            normal: Vec3::Z,
            distance: 4.0,
        };
        let drag = Drag::start(&pick, &pose);
        // The cursor ray now ends one metre to the right of the anchor.
        let ray = Ray {
            origin: Vec3::new(1.0, 0.0, 5.0),
            direction: -Vec3::Z,
        };
        let body = BodyState {
            pose,
            previous: pose,
            shape_id: 0,
            aabb: (Vec3::splat(-1.0), Vec3::ONE),
            bounding_radius: 1.0,
            center_of_mass: Vec3::ZERO,
            mass: 2.0,
            is_dynamic: true,
            is_kinematic: false,
            sleeping: false,
            visible: true,
            just_spawned: false,
            velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
            touching: 0,
            contact_points: 0,
        };
        let Some(Command::ApplyImpulse {
            body: id,
            impulse,
            point,
        }) = drag.push(&ray, &body, &pose, 0.01)
        else {
            panic!("no impulse");
        };
        assert_eq!(id, 3);
        assert!((impulse - DVec3::new(2.0 * 60.0 * 0.01, 0.0, 0.0)).length() < 1e-5);
        assert!((point - DVec3::Z).length() < 1e-6);
        let fixed = BodyState {
            is_dynamic: false,
            ..body
        };
        assert!(drag.push(&ray, &fixed, &pose, 0.01).is_none());
    }
}
