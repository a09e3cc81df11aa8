//! Scripted motions of kinematic bodies. A world knows velocities and target poses, not
//! scripts, so whatever steps a scene's world (the viewer's `Simulation`, `headless`) keeps
//! the scene's `ScriptedMotion`s and calls [`drive`] before each `World::step`.

use glam::{DQuat, DVec3};

use crate::physics::{BodyId, MotionError, World};
use crate::scene::error::FieldError;
use crate::scene::file::KinematicSpec;
use crate::scene::validate::{finite, non_negative, vector};

/// One kinematic body's script, with the pose it moves about.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScriptedMotion {
    /// The body, as `Scene::build_world` numbers it.
    pub body: BodyId,
    /// What the scene file asks.
    pub motion: KinematicSpec,
    /// The shape origin's position at rest (the body line's `position`, plus its copy's
    /// offset), m.
    pub rest_position: DVec3,
    /// The body line's `rotation`.
    pub rest_rotation: DQuat,
}

impl ScriptedMotion {
    /// The shape origin's position and the rotation at time `t`, s: where a `Sinusoid` puts
    /// the body; a `Velocity` body is at rest pose at t = 0 and moves on by itself.
    pub fn pose_at(&self, t: f64) -> (DVec3, DQuat) {
        match self.motion {
            KinematicSpec::Velocity { .. } => (self.rest_position, self.rest_rotation),
            KinematicSpec::Sinusoid {
                axis,
                amplitude,
                angle_axis,
                angle_amplitude,
                frequency,
                phase,
            } => {
                let s = (std::f64::consts::TAU * frequency * t + phase.to_radians()).sin();
                let shift = axis.normalize_or_zero() * (amplitude * s);
                let angle = (angle_amplitude * s).to_radians();
                let turn = DQuat::from_axis_angle(angle_axis.normalize_or(DVec3::Y), angle);
                (self.rest_position + shift, turn * self.rest_rotation)
            }
        }
    }

    /// Sets the body moving for a step of `dt` from the world's time: its velocities, or the
    /// pose it reaches at the end of the step.
    pub fn apply(&self, world: &mut World, dt: f64) -> Result<(), MotionError> {
        match self.motion {
            KinematicSpec::Velocity { linear, angular } => {
                world.set_kinematic_velocity(self.body, linear, angular)
            }
            KinematicSpec::Sinusoid { .. } => {
                let (position, rotation) = self.pose_at(world.time() + dt);
                world.set_kinematic_target(self.body, position, rotation)
            }
        }
    }
}

/// Call before `world.step(dt)`: every scripted body moves as its script says over the step.
/// A body removed or switched away from kinematic (the viewer can do both) is left alone, and
/// a backward step (`dt ≤ 0`) drives nothing: a script runs forward in time.
pub fn drive(scripts: &[ScriptedMotion], world: &mut World, dt: f64) {
    if dt <= 0.0 {
        return;
    }
    for script in scripts {
        // The errors say the body is no longer this script's to move, which is not a fault.
        let _ = script.apply(world, dt);
    }
}

/// Every number of a script: finite, a frequency not negative, and an axis wherever a swing
/// or a turn needs one.
pub(crate) fn check(motion: &KinematicSpec) -> Result<(), FieldError> {
    match *motion {
        KinematicSpec::Velocity { linear, angular } => {
            vector("linear", linear)?;
            vector("angular", angular)
        }
        KinematicSpec::Sinusoid {
            axis,
            amplitude,
            angle_axis,
            angle_amplitude,
            frequency,
            phase,
        } => {
            swing_axis("axis", axis, "amplitude", amplitude)?;
            swing_axis("angle_axis", angle_axis, "angle_amplitude", angle_amplitude)?;
            non_negative("frequency", frequency)?;
            finite("phase", phase)
        }
    }
}

fn swing_axis(
    field: &str,
    axis: DVec3,
    amplitude_field: &str,
    amplitude: f64,
) -> Result<(), FieldError> {
    vector(field, axis)?;
    finite(amplitude_field, amplitude)?;
    if amplitude != 0.0 && axis.length_squared() < 1e-24 {
        return Err(FieldError::new(
            field,
            format!("must not be zero when {amplitude_field} is not"),
        ));
    }
    Ok(())
}
