//! A joint as the world keeps it: its description turned into each body's own frame at
//! creation (so the joint holds the bodies as they were then), the impulses it ended the
//! last step with (for warm starting) and its reaction.

use glam::{DMat3, DQuat, DVec3};
use serde::{Deserialize, Serialize};

use super::desc::{Breaking, JointDesc, JointDrives, JointKind, Motor, Servo, Spring};
use crate::physics::dynamics::body::{BodyId, RigidBody};

/// The impulses a joint's rows ended the last substep with, N·s (N·m·s for the angular ones).
/// Each substep starts by applying them again (warm starting).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct JointImpulses {
    /// On b at the anchors (ball, hinge, fixed), world.
    pub point: DVec3,
    /// On b, turning (fixed and slider: all three axes; hinge: across its axis), world.
    pub angular: DVec3,
    /// Slider: along the two directions across its axis.
    pub across: [f64; 2],
    /// Along the axis or the distance: the equality or spring row.
    pub along: f64,
    /// The lower limit (never negative).
    pub lower: f64,
    /// The upper limit (never negative; it pushes the other way).
    pub upper: f64,
    /// The motor.
    pub motor: f64,
    /// The servo.
    pub servo: f64,
}

/// A joint between two bodies, as the world holds it (`World::joint`).
///
/// The fields a ball joint's rows read come first, then the other kinds', so that a pass over
/// the joints touches as few cache lines as it can (`joints::solve`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[repr(C)]
pub struct Joint {
    /// What the joint allows.
    pub kind: JointKind,
    /// The anchor on a, from its centre of mass in its body axes, m.
    pub local_anchor_a: DVec3,
    /// The anchor on b, from its centre of mass in its body axes, m.
    pub local_anchor_b: DVec3,
    /// What the rows ended the last step with.
    pub impulses: JointImpulses,
    /// A hinge's angle, rad: b's turn about the axis relative to a since creation, counted
    /// through whole turns (a wheel's keeps growing), so that limits beyond ±π and a
    /// limit near π hold; a cone-twist's twist, counted the same way. Zero for the other
    /// kinds.
    #[serde(default)]
    pub angle: f64,
    /// The unit axis in a's body axes (hinge, slider, cone-twist).
    pub local_axis_a: DVec3,
    /// The unit axis in b's body axes (hinge, cone-twist).
    pub local_axis_b: DVec3,
    /// A unit direction across the axis in a's body axes, from which a hinge angle is
    /// measured.
    pub local_reference_a: DVec3,
    /// The same direction in b's body axes at creation.
    pub local_reference_b: DVec3,
    /// b's orientation relative to a's at creation, q_a⁻¹ q_b (fixed, slider).
    pub relative_rotation: DQuat,
    /// As `JointDesc::cone`.
    #[serde(default = "half_turn")]
    pub cone: f64,
    /// The distance between the anchors at creation, m (distance joints' spring length).
    pub length: f64,
    /// As `JointDesc::limits`; a distance joint without limits or spring holds [length,
    /// length].
    pub limits: Option<(f64, f64)>,
    /// As `JointDesc::motor`.
    pub motor: Option<Motor>,
    /// As `JointDesc::servo`.
    #[serde(default)]
    pub servo: Option<Servo>,
    /// As `JointDesc::spring`.
    pub spring: Option<Spring>,
    /// The first body.
    pub body_a: BodyId,
    /// The second body.
    pub body_b: BodyId,
    /// As `JointDesc::breaking`.
    #[serde(default)]
    pub breaking: Option<Breaking>,
    /// Whether the two bodies collide with each other.
    pub collide_connected: bool,
    /// The force the joint put on b in the last step, N, world (a receives the opposite).
    pub reaction_force: DVec3,
    /// The torque the joint put on b in the last step about its anchor, N·m, world.
    pub reaction_torque: DVec3,
}

fn half_turn() -> f64 {
    std::f64::consts::PI
}

impl Joint {
    /// The joint of a validated description between the bodies as they are now.
    pub(crate) fn new(desc: &JointDesc, a: &RigidBody, b: &RigidBody) -> Joint {
        let to_a = a.orientation.transpose();
        let to_b = b.orientation.transpose();
        let axis = desc.axis.normalize_or(DVec3::Z);
        let reference = axis.any_orthonormal_vector();
        let limits = match (desc.kind, desc.limits, desc.spring) {
            (JointKind::Distance, None, None) => {
                let length = desc.anchor_a.distance(desc.anchor_b);
                Some((length, length))
            }
            (_, limits, _) => limits,
        };
        Joint {
            body_a: desc.body_a,
            body_b: desc.body_b,
            kind: desc.kind,
            local_anchor_a: to_a * (desc.anchor_a - a.position),
            local_anchor_b: to_b * (desc.anchor_b - b.position),
            local_axis_a: to_a * axis,
            local_axis_b: to_b * axis,
            cone: desc.cone,
            local_reference_a: to_a * reference,
            local_reference_b: to_b * reference,
            relative_rotation: (rotation_of(a.orientation).inverse() * rotation_of(b.orientation))
                .normalize(),
            length: desc.anchor_a.distance(desc.anchor_b),
            limits,
            motor: desc.motor,
            servo: desc.servo,
            breaking: desc.breaking,
            spring: desc.spring,
            collide_connected: desc.collide_connected,
            angle: 0.0,
            impulses: JointImpulses::default(),
            reaction_force: DVec3::ZERO,
            reaction_torque: DVec3::ZERO,
        }
    }

    /// Its motor, servo and spring (`World::set_joint_drives` changes them).
    pub fn drives(&self) -> JointDrives {
        JointDrives {
            motor: self.motor,
            servo: self.servo,
            spring: self.spring,
        }
    }

    /// Whether a motor or servo pushes its bodies toward a speed or pose of its own: a motor
    /// with a speed other than zero, a servo with a pull. Either can drive them slower
    /// than bodies fall asleep, which must not stop them (`islands::hold_driven_awake`).
    pub fn is_driven(&self) -> bool {
        let motor = self
            .motor
            .is_some_and(|m| m.speed != 0.0 && m.max_force > 0.0);
        let servo = self
            .servo
            .is_some_and(|s| s.hertz > 0.0 && s.max_force > 0.0);
        motor || servo
    }

    /// Whether the last step's reaction exceeded the joint's breaking load.
    pub fn overloaded(&self) -> bool {
        self.breaking.is_some_and(|b| {
            self.reaction_force.length() > b.force || self.reaction_torque.length() > b.torque
        })
    }

    /// Whether the joint holds body `index`.
    pub fn holds(&self, index: usize) -> bool {
        self.body_a.index() == index || self.body_b.index() == index
    }

    /// The numbers a hand-edited snapshot could break: finite, unit axes and rotation,
    /// limits in order, no negative spring or motor. The error names the field.
    pub(crate) fn check(&self) -> Result<(), String> {
        let vectors = [
            ("local_anchor_a", self.local_anchor_a),
            ("local_anchor_b", self.local_anchor_b),
            ("local_axis_a", self.local_axis_a),
            ("local_axis_b", self.local_axis_b),
            ("local_reference_a", self.local_reference_a),
            ("local_reference_b", self.local_reference_b),
            ("reaction_force", self.reaction_force),
            ("reaction_torque", self.reaction_torque),
            ("impulses.point", self.impulses.point),
            ("impulses.angular", self.impulses.angular),
        ];
        if let Some((field, _)) = vectors.iter().find(|(_, v)| !v.is_finite()) {
            return Err(format!("{field} is not finite"));
        }
        let units = [
            ("local_axis_a", self.local_axis_a),
            ("local_axis_b", self.local_axis_b),
            ("local_reference_a", self.local_reference_a),
            ("local_reference_b", self.local_reference_b),
        ];
        if let Some((field, _)) = units.iter().find(|(_, v)| (v.length() - 1.0).abs() > 1e-9) {
            return Err(format!("{field} is not a unit vector"));
        }
        let q = self.relative_rotation;
        if !q.is_finite() || (q.length() - 1.0).abs() > 1e-9 {
            return Err("relative_rotation is not a unit quaternion".into());
        }
        let i = &self.impulses;
        let scalars = [
            i.across[0],
            i.across[1],
            i.along,
            i.lower,
            i.upper,
            i.motor,
            i.servo,
        ];
        if !self.angle.is_finite() {
            return Err(format!("angle must be finite, got {}", self.angle));
        }
        if !self.length.is_finite() || self.length <= 0.0 && self.kind == JointKind::Distance {
            return Err(format!(
                "length must be finite and positive, got {}",
                self.length
            ));
        }
        if scalars.iter().any(|s| !s.is_finite()) || i.lower < 0.0 || i.upper < 0.0 {
            return Err("impulses must be finite, the limits' not negative".into());
        }
        let desc = JointDesc {
            limits: self.limits,
            motor: self.motor,
            servo: self.servo,
            breaking: self.breaking,
            spring: self.spring,
            cone: self.cone,
            ..JointDesc::distance(self.body_a, self.body_b, DVec3::ZERO, DVec3::X)
        };
        let desc = JointDesc {
            kind: self.kind,
            ..desc
        };
        desc.validate().map_err(|e| e.to_string())
    }
}

/// A rotation matrix as a unit quaternion.
pub(crate) fn rotation_of(orientation: DMat3) -> DQuat {
    DQuat::from_mat3(&orientation).normalize()
}
