//! Kinematic bodies and changes of motion: a kinematic body's velocity or target pose, and
//! switching a body between dynamic, kinematic and static while the world runs.

use glam::{DMat3, DQuat, DVec3};

use super::World;
use crate::physics::dynamics::body::{BodyError, BodyId, Motion, RigidBody};

/// Why a change of a body's motion was refused; the world is left as it was.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MotionError {
    /// No body has this id (or it names a removed body).
    #[error("there is no body {0}")]
    NoSuchBody(u32),
    /// The body was isolated for going non-finite.
    #[error("body {0} no longer takes part in the simulation")]
    BodyGone(u32),
    /// A kinematic velocity or target for a body that is not kinematic.
    #[error("body {0} is not kinematic")]
    NotKinematic(u32),
    /// A velocity, position or rotation that is not finite (or a zero rotation).
    #[error("{0} must be finite")]
    NotFinite(&'static str),
    /// `set_motion` takes `Dynamic`, `Kinematic` or `Static`; the world alone isolates and
    /// removes bodies.
    #[error("a body cannot be made {0:?}")]
    NotAMotion(Motion),
    /// The body's shape and material give no mass a dynamic body can have.
    #[error(transparent)]
    Mass(#[from] BodyError),
}

impl World {
    /// Sets a kinematic body's velocity, m/s, and angular velocity, rad/s (world), which it
    /// keeps until changed; a pending target is dropped. The body wakes.
    pub fn set_kinematic_velocity(
        &mut self,
        id: BodyId,
        velocity: DVec3,
        angular_velocity: DVec3,
    ) -> Result<(), MotionError> {
        let body = self.kinematic_mut(id)?;
        if !velocity.is_finite() || !angular_velocity.is_finite() {
            return Err(MotionError::NotFinite("velocity"));
        }
        body.kinematic_velocity = velocity;
        body.kinematic_spin = angular_velocity;
        body.kinematic_target = None;
        Ok(())
    }

    /// Makes a kinematic body reach this pose (its shape's origin, as `BodyDesc::at`, and
    /// rotation) at the end of the next step: for that step its velocity is the displacement
    /// over dt (and its angular velocity the turn over dt), and it stops there.
    pub fn set_kinematic_target(
        &mut self,
        id: BodyId,
        position: DVec3,
        rotation: DQuat,
    ) -> Result<(), MotionError> {
        let body = self.kinematic_mut(id)?;
        if !position.is_finite() {
            return Err(MotionError::NotFinite("position"));
        }
        if !rotation.is_finite() || rotation.length_squared() < 1e-12 {
            return Err(MotionError::NotFinite("rotation"));
        }
        body.kinematic_target = Some((position, rotation.normalize()));
        Ok(())
    }

    /// Switches a body between `Dynamic`, `Kinematic` and `Static`. A body made kinematic
    /// keeps its velocities; one made dynamic gets the mass it was created with and a
    /// kinematic body's velocities; a static one stops. The body and whatever its box
    /// touches wake.
    pub fn set_motion(&mut self, id: BodyId, motion: Motion) -> Result<(), MotionError> {
        if !matches!(motion, Motion::Dynamic | Motion::Kinematic | Motion::Static) {
            return Err(MotionError::NotAMotion(motion));
        }
        let body = self.moving_part_mut(id)?;
        if body.motion == motion {
            return Ok(());
        }
        let dynamic_inverses = match motion {
            Motion::Dynamic => Some(body.dynamic_mass_properties()?),
            _ => None,
        };
        switch_motion(body, motion, dynamic_inverses);
        self.wake_neighbours(id.index());
        Ok(())
    }

    /// The kinematic body `id`, woken and looked at again by the next step.
    fn kinematic_mut(&mut self, id: BodyId) -> Result<&mut RigidBody, MotionError> {
        let body = self.moving_part_mut(id)?;
        if !body.is_kinematic() {
            return Err(MotionError::NotKinematic(id.0));
        }
        Ok(body)
    }

    /// The body `id` if it takes part, woken and looked at again by the next step.
    fn moving_part_mut(&mut self, id: BodyId) -> Result<&mut RigidBody, MotionError> {
        match self.get_body(id).map(|b| b.motion) {
            None => return Err(MotionError::NoSuchBody(id.0)),
            Some(motion) if !motion.takes_part() => return Err(MotionError::BodyGone(id.0)),
            Some(_) => {}
        }
        self.awake_set.touch(id.index());
        let body = &mut self.bodies[id.index()];
        body.wake();
        Ok(body)
    }

    /// Before a forward step of `dt`: each kinematic body with a target gets the velocities
    /// that take it there in the step.
    pub(super) fn aim_kinematic_targets(&mut self, dt: f64) {
        for &index in self.awake_set.awake(&self.bodies) {
            let body = &mut self.bodies[index as usize];
            if let Some((position, rotation)) = body.kinematic_target.filter(|_| dt > 0.0) {
                let centre = position + DMat3::from_quat(rotation) * body.local_center;
                body.kinematic_velocity = (centre - body.position) / dt;
                let mut turn = rotation * body.rotation().inverse();
                if turn.w < 0.0 {
                    turn = -turn;
                }
                let (axis, angle) = turn.to_axis_angle();
                body.kinematic_spin = axis * (angle / dt);
            }
        }
    }

    /// After a forward step: each kinematic body with a target is put exactly on it (the
    /// step's motion reached it up to round-off) and stops.
    pub(super) fn arrive_at_kinematic_targets(&mut self, dt: f64) {
        if dt <= 0.0 {
            return;
        }
        for &index in self.awake_set.awake(&self.bodies) {
            let body = &mut self.bodies[index as usize];
            if let Some((position, rotation)) = body.kinematic_target.take() {
                body.orientation = DMat3::from_quat(rotation);
                body.position = position + body.orientation * body.local_center;
                body.refresh_world_inertia();
                body.kinematic_velocity = DVec3::ZERO;
                body.kinematic_spin = DVec3::ZERO;
            }
        }
    }
}

/// Changes a body's motion, its masses and momenta with it (`dynamic_inverses`: 1/m and
/// I⁻¹ when it becomes dynamic).
fn switch_motion(body: &mut RigidBody, motion: Motion, dynamic_inverses: Option<(f64, DMat3)>) {
    let (velocity, spin) = (body.velocity(), body.angular_velocity());
    let (inv_mass, inv_inertia_local) = dynamic_inverses.unwrap_or((0.0, DMat3::ZERO));
    body.motion = motion;
    body.inv_mass = inv_mass;
    body.inv_inertia_local = inv_inertia_local;
    body.refresh_world_inertia();
    body.linear_momentum = DVec3::ZERO;
    body.angular_momentum = DVec3::ZERO;
    body.kinematic_velocity = DVec3::ZERO;
    body.kinematic_spin = DVec3::ZERO;
    body.kinematic_target = None;
    match motion {
        Motion::Dynamic => {
            body.linear_momentum = velocity * body.mass();
            body.angular_momentum = body.inertia_world() * spin;
        }
        Motion::Kinematic => {
            body.kinematic_velocity = velocity;
            body.kinematic_spin = spin;
        }
        _ => {}
    }
}
