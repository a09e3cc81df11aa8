//! What a user asks for: a joint between two bodies, with world-space anchors and axes at
//! creation (`JointDesc`), its optional limits, motor and spring, and the typed errors
//! `World::add_joint` gives for a description it cannot build.

use glam::DVec3;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::physics::dynamics::body::BodyId;

/// The kinds of joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum JointKind {
    /// Spherical: the anchors coincide; every rotation is free.
    Ball,
    /// Revolute: the anchors coincide and the bodies turn about one axis only.
    Hinge,
    /// Prismatic: no relative rotation; the anchors slide along one axis only.
    Slider,
    /// Weld: no relative motion at all.
    Fixed,
    /// The anchors stay a length apart (a rod), within `[min, max]` (a rope), or are pulled
    /// toward the length by a spring.
    Distance,
    /// Spherical with limits, for shoulders and hips: b's axis stays within a cone about a's
    /// (`JointDesc::cone`), and b's twist about it within `limits`.
    ConeTwist,
}

/// A motor that drives a hinge's relative angular speed (rad/s, with a torque limit in N·m)
/// or a slider's relative speed along its axis (m/s, with a force limit in N).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Motor {
    /// Target speed of body b relative to body a about or along the axis.
    pub speed: f64,
    /// The largest torque (hinge) or force (slider) the motor gives, ≥ 0.
    pub max_force: f64,
}

/// A servo on a hinge or slider: b is pulled about (rad) or along (m) the axis toward a target
/// angle or offset by a spring, with at most `max_force`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Servo {
    /// The angle (hinge, rad, counted through whole turns) or offset (slider, m) of b
    /// relative to a, from the pose at creation.
    pub target: f64,
    /// Natural frequency of the pull, Hz, ≥ 0 (0: no pull).
    pub hertz: f64,
    /// Damping ratio of the pull, ≥ 0 (1: critically damped).
    pub damping_ratio: f64,
    /// The largest torque (hinge) or force (slider) the servo gives, ≥ 0.
    pub max_force: f64,
}

/// The load at which a joint breaks: the world takes it out after a step in which its
/// reaction on b exceeded either (infinity: never on that count).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Breaking {
    /// N, > 0.
    pub force: f64,
    /// N·m, about b's anchor, > 0.
    pub torque: f64,
}

/// A spring along a distance joint, toward the length at creation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Spring {
    /// Natural frequency, Hz, ≥ 0 (0: no spring force, the limits alone act).
    pub hertz: f64,
    /// Damping ratio, ≥ 0 (1: critically damped).
    pub damping_ratio: f64,
}

/// Everything needed to join two bodies (`World::add_joint`). Anchors and axes are in world
/// coordinates at the moment the joint is added: the joint holds the bodies as they are then.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointDesc {
    /// The first body.
    pub body_a: BodyId,
    /// The second body: limits, motors and reactions are of b relative to a.
    pub body_b: BodyId,
    /// What the joint allows.
    pub kind: JointKind,
    /// The anchor on body a, world, m.
    pub anchor_a: DVec3,
    /// The anchor on body b, world, m (the same point as `anchor_a` except for distance).
    pub anchor_b: DVec3,
    /// The hinge, slider or cone-twist axis, world (any length but zero); unused by the
    /// other kinds.
    pub axis: DVec3,
    /// Cone-twist: the greatest angle between the two bodies' axes, rad, in (0, π].
    pub cone: f64,
    /// Hinge: angles, rad, of b relative to a about the axis from the pose at creation;
    /// slider: offsets along the axis, m; distance: the least and greatest length, m.
    pub limits: Option<(f64, f64)>,
    /// Hinge or slider motor.
    pub motor: Option<Motor>,
    /// Hinge or slider servo (not with a motor).
    pub servo: Option<Servo>,
    /// Distance spring.
    pub spring: Option<Spring>,
    /// When the joint breaks; None: never.
    pub breaking: Option<Breaking>,
    /// Whether the two bodies still collide with each other (off by default: a joint's
    /// bodies usually overlap at the anchor).
    pub collide_connected: bool,
}

impl JointDesc {
    fn new(kind: JointKind, a: BodyId, b: BodyId, anchor_a: DVec3, anchor_b: DVec3) -> Self {
        JointDesc {
            body_a: a,
            body_b: b,
            kind,
            anchor_a,
            anchor_b,
            axis: DVec3::Z,
            cone: std::f64::consts::PI,
            limits: None,
            motor: None,
            servo: None,
            spring: None,
            breaking: None,
            collide_connected: false,
        }
    }

    /// A ball joint at the world point `anchor`.
    pub fn ball(a: BodyId, b: BodyId, anchor: DVec3) -> Self {
        JointDesc::new(JointKind::Ball, a, b, anchor, anchor)
    }

    /// A hinge at `anchor` about the world `axis`.
    pub fn hinge(a: BodyId, b: BodyId, anchor: DVec3, axis: DVec3) -> Self {
        JointDesc {
            axis,
            ..JointDesc::new(JointKind::Hinge, a, b, anchor, anchor)
        }
    }

    /// A slider through `anchor` along the world `axis`.
    pub fn slider(a: BodyId, b: BodyId, anchor: DVec3, axis: DVec3) -> Self {
        JointDesc {
            axis,
            ..JointDesc::new(JointKind::Slider, a, b, anchor, anchor)
        }
    }

    /// A ball joint at `anchor` whose bodies' axes, both along the world `axis` at creation,
    /// stay within `cone` rad of each other; `with_limits` bounds the twist about them (rad).
    pub fn cone_twist(a: BodyId, b: BodyId, anchor: DVec3, axis: DVec3, cone: f64) -> Self {
        JointDesc {
            axis,
            cone,
            ..JointDesc::new(JointKind::ConeTwist, a, b, anchor, anchor)
        }
    }

    /// A weld at `anchor` (where the reaction is measured).
    pub fn fixed(a: BodyId, b: BodyId, anchor: DVec3) -> Self {
        JointDesc::new(JointKind::Fixed, a, b, anchor, anchor)
    }

    /// A rod between `anchor_a` on a and `anchor_b` on b, of their distance at creation;
    /// `with_limits` makes it a rope, `with_spring` a spring.
    pub fn distance(a: BodyId, b: BodyId, anchor_a: DVec3, anchor_b: DVec3) -> Self {
        JointDesc::new(JointKind::Distance, a, b, anchor_a, anchor_b)
    }

    /// Sets `limits`: `lo ≤ hi` (rad for a hinge, m for a slider and distance).
    pub fn with_limits(mut self, lo: f64, hi: f64) -> Self {
        self.limits = Some((lo, hi));
        self
    }

    /// Sets `motor`: a target `speed` and the largest torque or force `max_force`.
    pub fn with_motor(mut self, speed: f64, max_force: f64) -> Self {
        self.motor = Some(Motor { speed, max_force });
        self
    }

    /// Sets `servo`: toward `target` (rad for a hinge, m for a slider) with a spring of
    /// `hertz` and `damping_ratio`, by at most `max_force` (N·m or N).
    pub fn with_servo(
        mut self,
        target: f64,
        hertz: f64,
        damping_ratio: f64,
        max_force: f64,
    ) -> Self {
        self.servo = Some(Servo {
            target,
            hertz,
            damping_ratio,
            max_force,
        });
        self
    }

    /// Sets `breaking`: the joint breaks in a step whose reaction exceeds `force` N or
    /// `torque` N·m (`f64::INFINITY` to break on the other alone).
    pub fn with_breaking(mut self, force: f64, torque: f64) -> Self {
        self.breaking = Some(Breaking { force, torque });
        self
    }

    /// Sets `spring`.
    pub fn with_spring(mut self, hertz: f64, damping_ratio: f64) -> Self {
        self.spring = Some(Spring {
            hertz,
            damping_ratio,
        });
        self
    }

    /// Sets `collide_connected`.
    pub fn colliding(mut self, collide: bool) -> Self {
        self.collide_connected = collide;
        self
    }

    /// Checks what does not depend on the bodies: finite numbers, a usable axis, limits in
    /// order, non-negative spring and motor, and options the kind has.
    pub fn validate(&self) -> Result<(), JointError> {
        if self.body_a == self.body_b {
            return Err(JointError::SameBody(self.body_a.0));
        }
        for (field, value) in [("anchor_a", self.anchor_a), ("anchor_b", self.anchor_b)] {
            if !value.is_finite() {
                return Err(JointError::NotFinite(field));
            }
        }
        if self.kind == JointKind::ConeTwist
            && !(self.cone > 0.0 && self.cone <= std::f64::consts::PI)
        {
            return Err(JointError::ConeOutOfRange(self.cone));
        }
        if matches!(
            self.kind,
            JointKind::Hinge | JointKind::Slider | JointKind::ConeTwist
        ) {
            if !self.axis.is_finite() {
                return Err(JointError::NotFinite("axis"));
            }
            if self.axis.length_squared() < 1e-24 {
                return Err(JointError::ZeroAxis);
            }
        }
        if self.kind == JointKind::Distance && self.anchor_a.distance(self.anchor_b) < 1e-9 {
            return Err(JointError::ZeroLength);
        }
        self.validate_options()
    }

    fn validate_options(&self) -> Result<(), JointError> {
        if let Some((lo, hi)) = self.limits {
            if lo.is_nan() || hi.is_nan() || lo == f64::INFINITY || hi == f64::NEG_INFINITY {
                return Err(JointError::NotFinite("limits"));
            }
            if lo > hi {
                return Err(JointError::LimitsOutOfOrder { lo, hi });
            }
            let no_limits = matches!(self.kind, JointKind::Ball | JointKind::Fixed);
            if no_limits || (self.kind == JointKind::Distance && lo < 0.0) {
                return Err(JointError::Unsupported("limits"));
            }
        }
        self.drives().check(self.kind)?;
        if let Some(breaking) = self.breaking {
            for (field, value) in [
                ("breaking.force", breaking.force),
                ("breaking.torque", breaking.torque),
            ] {
                if value.is_nan() {
                    return Err(JointError::NotFinite(field));
                }
                if value <= 0.0 {
                    return Err(JointError::NotPositive { field, value });
                }
            }
        }
        Ok(())
    }
}

/// What drives a joint about or along its axis, or pulls it toward its length: the options
/// a game or the viewer's panel changes while the world runs (`World::set_joint_drives`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct JointDrives {
    /// As `JointDesc::motor`: hinge and slider.
    pub motor: Option<Motor>,
    /// As `JointDesc::servo`: hinge and slider, not with a motor.
    pub servo: Option<Servo>,
    /// As `JointDesc::spring`: distance joints.
    pub spring: Option<Spring>,
}

impl JointDrives {
    /// What `JointDesc::validate` refuses of these on a joint of this kind.
    pub fn check(&self, kind: JointKind) -> Result<(), JointError> {
        let axial = matches!(kind, JointKind::Hinge | JointKind::Slider);
        if let Some(motor) = self.motor {
            check_non_negative("motor.max_force", motor.max_force)?;
            if !motor.speed.is_finite() {
                return Err(JointError::NotFinite("motor.speed"));
            }
            if !axial {
                return Err(JointError::Unsupported("motor"));
            }
        }
        if let Some(servo) = self.servo {
            if !servo.target.is_finite() {
                return Err(JointError::NotFinite("servo.target"));
            }
            check_non_negative("servo.hertz", servo.hertz)?;
            check_non_negative("servo.damping_ratio", servo.damping_ratio)?;
            check_non_negative("servo.max_force", servo.max_force)?;
            if !axial {
                return Err(JointError::Unsupported("servo"));
            }
            if self.motor.is_some() {
                return Err(JointError::MotorAndServo);
            }
        }
        if let Some(spring) = self.spring {
            check_non_negative("spring.hertz", spring.hertz)?;
            check_non_negative("spring.damping_ratio", spring.damping_ratio)?;
            if kind != JointKind::Distance {
                return Err(JointError::Unsupported("spring"));
            }
        }
        Ok(())
    }
}

impl JointDesc {
    fn drives(&self) -> JointDrives {
        JointDrives {
            motor: self.motor,
            servo: self.servo,
            spring: self.spring,
        }
    }
}

fn check_non_negative(field: &'static str, value: f64) -> Result<(), JointError> {
    if !value.is_finite() {
        return Err(JointError::NotFinite(field));
    }
    if value < 0.0 {
        return Err(JointError::Negative { field, value });
    }
    Ok(())
}

/// Index of a joint in its world, as `World::add_joint` hands it out; it stays valid (and
/// names no other joint) after the joint is removed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct JointId(pub u32);

/// Why `World::add_joint` or `World::remove_joint` refused; the world is left as it was.
#[derive(Debug, Error, PartialEq)]
pub enum JointError {
    /// No body has this id (or it names a removed body).
    #[error("there is no body {0}")]
    NoSuchBody(u32),
    /// A cone-twist joint's cone is not an angle in (0, π].
    #[error("the cone must be an angle in (0, π] rad, got {0}")]
    ConeOutOfRange(f64),
    /// A joint has a motor and a servo, which would pull against each other.
    #[error("a joint takes a motor or a servo, not both")]
    MotorAndServo,
    /// The body was isolated for going non-finite.
    #[error("body {0} no longer takes part in the simulation")]
    BodyGone(u32),
    /// Both ends name the same body.
    #[error("a joint needs two bodies, got body {0} twice")]
    SameBody(u32),
    /// Neither body is dynamic (static or kinematic), so the joint could move nothing.
    #[error("neither body of a joint is dynamic")]
    NoDynamicBody,
    /// A number is NaN or infinite.
    #[error("{0} must be finite")]
    NotFinite(&'static str),
    /// The hinge or slider axis has no direction.
    #[error("the axis must not be zero")]
    ZeroAxis,
    /// A distance joint's anchors coincide: it has no direction to hold.
    #[error("a distance joint's anchors must not coincide")]
    ZeroLength,
    /// `with_limits(lo, hi)` with lo > hi.
    #[error("limits must be in order, got lo = {lo} > hi = {hi}")]
    LimitsOutOfOrder {
        /// The lower limit given.
        lo: f64,
        /// The upper limit given.
        hi: f64,
    },
    /// A breaking load that is zero or below.
    #[error("{field} must be positive, got {value}")]
    NotPositive {
        /// The field.
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// A spring, servo or motor value below zero.
    #[error("{field} must not be negative, got {value}")]
    Negative {
        /// The field.
        field: &'static str,
        /// The value given.
        value: f64,
    },
    /// An option this kind of joint does not have (limits on a ball joint, a negative
    /// length, a spring on a hinge, a motor on a distance joint).
    #[error("this kind of joint takes no such {0}")]
    Unsupported(&'static str),
    /// No joint has this id, or it was removed.
    #[error("there is no joint {0}")]
    NoSuchJoint(u32),
}
