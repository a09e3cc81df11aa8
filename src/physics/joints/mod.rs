//! Joints: constraints that hold two bodies together (ball, hinge, slider, fixed,
//! distance), with limits, motors and springs.
//!
//! - `desc`: what a user asks for (`JointDesc`, world-space anchors and axes) and the typed
//!   errors for what cannot be built;
//! - `joint`: the joint as a world keeps it, in its bodies' own frames, with the impulses
//!   it ended the last step with and its reaction;
//! - `rows`: the soft constraint rows (anchors together, no turn, along a direction, about
//!   an axis) on two bodies' velocities;
//! - `ball`: a ball joint's pass, in lanes;
//! - `solve`: the joints' stages inside the soft step (prepare, warm start, biased and relax
//!   passes, finish).
//!
//! Joints are soft constraints in the same substeps as the contacts: warm started from the
//! last step, solved with a stiff spring's bias (`SoftSolverSettings::joint_hertz`), then
//! relaxed without it. The classic pipeline has no joints and refuses a world that holds
//! any (`StepError::JointsNeedSoft`).

mod ball;
pub mod desc;
pub mod joint;
pub(crate) mod rows;
pub(crate) mod solve;

pub use desc::{
    Breaking, JointDesc, JointDrives, JointError, JointId, JointKind, Motor, Servo, Spring,
};
pub use joint::{Joint, JointImpulses};
