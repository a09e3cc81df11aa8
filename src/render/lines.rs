//! Line overlays as vertex pairs: the ground grid, bounding boxes, velocity vectors, joints
//! and any segments the simulation supplies (contacts).

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use crate::sim::snapshot::{BodyPose, JointSketch};
use crate::sim::{BodyState, LineSegment};

#[repr(C)]
/// One end of a line segment, as the line pipelines read it.
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct LineVertex {
    /// World space.
    pub position: [f32; 3],
    /// Gamma-encoded RGBA; alpha blends the line over what is behind it.
    pub color: [f32; 4],
}

/// Overlay colours (gamma-encoded RGB, as they appear on screen). The tests look for them.
pub const AABB_COLOR: [f32; 3] = [1.0, 0.85, 0.1];
/// Cyan, apart from the AABB yellow: the broad phase's grown boxes.
pub const BROAD_PHASE_COLOR: [f32; 3] = [0.1, 0.9, 0.9];
/// Magenta: the uniform grid's occupied cells, apart from the boxes inside them.
pub const GRID_CELL_COLOR: [f32; 3] = [0.95, 0.2, 0.85];
/// The velocity arrows.
pub const VELOCITY_COLOR: [f32; 3] = [0.1, 0.9, 1.0];
/// Lime, apart from the contacts' yellow and orange: the joints.
pub const JOINT_COLOR: [f32; 3] = [0.45, 1.0, 0.2];
/// Half the length of a drawn joint axis, and half the size of the cross at an anchor, m.
const JOINT_AXIS_HALF: f32 = 0.2;
const JOINT_CROSS_HALF: f32 = 0.04;
const GRID_COLOR: [f32; 4] = [0.35, 0.38, 0.42, 0.6];

/// Grid half-size (m) and spacing: enough to ground every built-in scene.
const GRID_HALF: i32 = 12;
/// Slightly below y = 0 so that floors whose top is at 0 hide it instead of flickering.
const GRID_Y: f32 = -0.02;

/// Line segments to draw, built up on the CPU for one frame.
#[derive(Default)]
pub struct LineList {
    /// Two vertices per segment, in order (a line-list topology).
    pub vertices: Vec<LineVertex>,
}

impl LineList {
    /// Adds the segment from `from` to `to` (world space) in `color` (gamma-encoded RGBA).
    pub fn segment(&mut self, from: Vec3, to: Vec3, color: [f32; 4]) {
        self.vertices.push(LineVertex {
            position: from.into(),
            color,
        });
        self.vertices.push(LineVertex {
            position: to.into(),
            color,
        });
    }

    /// The ground grid: lines 1 m apart from -12 m to 12 m along x and z, in a translucent
    /// grey just below y = 0.
    pub fn grid(&mut self) {
        let extent = GRID_HALF as f32;
        for i in -GRID_HALF..=GRID_HALF {
            let t = i as f32;
            self.segment(
                Vec3::new(t, GRID_Y, -extent),
                Vec3::new(t, GRID_Y, extent),
                GRID_COLOR,
            );
            self.segment(
                Vec3::new(-extent, GRID_Y, t),
                Vec3::new(extent, GRID_Y, t),
                GRID_COLOR,
            );
        }
    }

    /// The twelve edges of the axis-aligned box from `min` to `max` (world space), opaque
    /// in `color` (gamma-encoded RGB).
    pub fn aabb(&mut self, min: Vec3, max: Vec3, color: [f32; 3]) {
        let color = opaque(color);
        let corner = |i: usize| {
            Vec3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            )
        };
        for i in 0..8 {
            for bit in [1, 2, 4] {
                if i & bit == 0 {
                    self.segment(corner(i), corner(i | bit), color);
                }
            }
        }
    }

    /// An arrow for a body's velocity, from its centre of mass, 0.25 s of travel long.
    pub fn velocity(&mut self, body: &BodyState) {
        let color = opaque(VELOCITY_COLOR);
        let from = body.center_of_mass;
        let arrow = body.velocity * 0.25;
        if arrow.length_squared() < 1e-6 {
            return;
        }
        let to = from + arrow;
        self.segment(from, to, color);
        // Two short barbs in the plane of the arrow and the world up (or x) axis.
        let side = arrow.cross(Vec3::Y).try_normalize().unwrap_or(Vec3::X);
        let back = -arrow.normalize() * (0.2 * arrow.length()).min(0.3);
        for s in [-1.0, 1.0] {
            self.segment(to, to + back + side * back.length() * 0.5 * s, color);
        }
    }

    /// Adds a joint at its bodies' drawn `poses` (a, b): the anchors joined (a rod or rope's
    /// length; a point otherwise), origin to anchor on each moving body, a cross at a's
    /// anchor and the axis through it.
    pub fn joint(&mut self, sketch: &JointSketch, poses: [BodyPose; 2]) {
        let color = opaque(JOINT_COLOR);
        let at = |k: usize| poses[k].position + poses[k].rotation * sketch.anchors[k];
        let anchors = [at(0), at(1)];
        self.segment(anchors[0], anchors[1], color);
        for k in (0..2).filter(|&k| sketch.moving[k]) {
            self.segment(poses[k].position, anchors[k], color);
        }
        let anchor_a = anchors[0];
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            let arm = axis * JOINT_CROSS_HALF;
            self.segment(anchor_a - arm, anchor_a + arm, color);
        }
        if let Some(axis) = sketch.axis {
            let arm = poses[0].rotation * axis * JOINT_AXIS_HALF;
            self.segment(anchor_a - arm, anchor_a + arm, color);
        }
    }

    /// Adds the simulation's segments (contacts, the drag spring), opaque in their own
    /// colours.
    pub fn segments(&mut self, segments: &[LineSegment]) {
        for s in segments {
            self.segment(s.from, s.to, opaque(s.color));
        }
    }
}

/// An RGB colour as RGBA, fully opaque.
fn opaque([r, g, b]: [f32; 3]) -> [f32; 4] {
    [r, g, b, 1.0]
}

#[cfg(test)]
mod tests {
    use glam::Quat;

    use super::*;

    /// A joint's lines end at its anchors, carried by the bodies' poses.
    #[test]
    fn a_joint_is_drawn_between_its_anchors_at_the_poses() {
        let sketch = JointSketch {
            bodies: [0, 1],
            anchors: [Vec3::new(0.0, -0.5, 0.0), Vec3::new(0.0, 0.5, 0.0)],
            axis: Some(Vec3::Z),
            moving: [true, true],
        };
        let turned = Quat::from_rotation_x(std::f32::consts::FRAC_PI_2);
        let poses = [
            BodyPose {
                position: Vec3::ZERO,
                rotation: Quat::IDENTITY,
            },
            BodyPose {
                position: Vec3::new(0.0, -2.0, 0.0),
                rotation: turned,
            },
        ];
        let mut lines = LineList::default();
        lines.joint(&sketch, poses);
        let at = |k: usize| Vec3::from(lines.vertices[k].position);
        // Anchor a → anchor b (b turned a quarter about x: its anchor (0, 0.5, 0) at z = 0.5),
        // then origin → anchor on each body.
        assert!(at(0).distance(Vec3::new(0.0, -0.5, 0.0)) < 1e-6);
        assert!(
            at(1).distance(Vec3::new(0.0, -2.0, 0.5)) < 1e-6,
            "{}",
            at(1)
        );
        assert!(at(2).distance(Vec3::ZERO) < 1e-6 && at(3).distance(at(0)) < 1e-6);
        assert!(at(4).distance(poses[1].position) < 1e-6 && at(5).distance(at(1)) < 1e-6);
        // A static body's arm is left out.
        let mut fixed_a = LineList::default();
        let sketch = JointSketch {
            moving: [false, true],
            ..sketch
        };
        fixed_a.joint(&sketch, poses);
        assert_eq!(fixed_a.vertices.len(), lines.vertices.len() - 2);
        // The axis (last segment) through a's anchor along a's z.
        let n = lines.vertices.len();
        let axis =
            Vec3::from(lines.vertices[n - 1].position) - Vec3::from(lines.vertices[n - 2].position);
        assert!((axis.normalize() - Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn aabb_has_twelve_edges_on_the_box() {
        let mut lines = LineList::default();
        lines.aabb(Vec3::ZERO, Vec3::ONE, AABB_COLOR);
        assert_eq!(lines.vertices.len(), 24);
        for pair in lines.vertices.chunks(2) {
            let d = Vec3::from(pair[1].position) - Vec3::from(pair[0].position);
            assert!((d.length() - 1.0).abs() < 1e-6);
        }
    }
}
