//! Checks on the numbers of a scene that serde cannot make: finiteness (RON accepts `NaN` and
//! `inf`), signs, ranges and limits. Scene-level checks live here; body checks are made while
//! each body is built (`build.rs`, `shapes.rs`) with the helpers below.

use std::ops::RangeInclusive;

use glam::DVec3;

use crate::physics::Material;
use crate::physics::geometry::shape::{MAX_EXTENT, MIN_EXTENT};
use crate::scene::build::to_force;
use crate::scene::error::{FieldError, SceneError};
use crate::scene::file::{Camera, ForceSpec, Scene};

/// Most bodies a scene may create, generators included: the most a world holds.
pub use crate::physics::MAX_BODIES;

/// Accepted time steps, s: below a microsecond nothing visible ever happens, above 0.1 s the
/// integrators are no longer meaningful for bodies of everyday size.
pub const DT_RANGE: RangeInclusive<f64> = 1e-6..=0.1;

/// The largest friction coefficient accepted: the engine's own bound.
pub use crate::physics::MAX_FRICTION;

/// Everything about a scene that is not a body.
pub(crate) fn check_scene(scene: &Scene) -> Result<(), SceneError> {
    let file = scene.origin.as_str();
    if scene.name.trim().is_empty() {
        return Err(FieldError::new("name", "must not be empty").in_scene(file));
    }
    in_range("settings.dt", scene.settings.dt, DT_RANGE).map_err(|e| e.in_scene(file))?;
    check_camera(&scene.camera).map_err(|e| e.in_scene(file))?;
    for (index, force) in scene.forces.iter().enumerate() {
        check_force(force).map_err(|e| e.within(&format!("forces[{index}]")).in_scene(file))?;
    }
    for (name, material) in &scene.materials {
        check_material(material).map_err(|e| e.in_material(file, name))?;
    }
    check_body_count(scene)
}

fn check_camera(camera: &Camera) -> Result<(), FieldError> {
    vector("camera.eye", camera.eye)?;
    vector("camera.target", camera.target)?;
    if camera.eye.distance(camera.target) < MIN_EXTENT {
        return Err(FieldError::new(
            "camera.target",
            "must differ from camera.eye",
        ));
    }
    Ok(())
}

/// Finite first (naming the component), then within the engine's limits
/// (`EnvironmentForce::validate`).
fn check_force(force: &ForceSpec) -> Result<(), FieldError> {
    match *force {
        ForceSpec::Gravity { acceleration } => vector("acceleration", acceleration)?,
        ForceSpec::LinearDrag { coefficient } | ForceSpec::QuadraticDrag { coefficient } => {
            non_negative("coefficient", coefficient)?
        }
        ForceSpec::Wind {
            velocity,
            coefficient,
        } => {
            vector("velocity", velocity)?;
            non_negative("coefficient", coefficient)?
        }
    }
    to_force(force)
        .validate()
        .map_err(|e| FieldError::new(e.field, e.reason))
}

/// Density, restitution and friction, for named and inline materials alike.
pub(crate) fn check_material(material: &Material) -> Result<(), FieldError> {
    positive("density", material.density)?;
    in_range("restitution", material.restitution, 0.0..=1.0)?;
    in_range("friction", material.friction, 0.0..=MAX_FRICTION)
}

fn check_body_count(scene: &Scene) -> Result<(), SceneError> {
    let count = scene.body_count();
    if count > MAX_BODIES as u64 {
        return Err(SceneError::TooManyBodies {
            file: scene.origin.clone(),
            count,
            limit: MAX_BODIES,
        });
    }
    Ok(())
}

pub(crate) fn finite(field: &str, value: f64) -> Result<(), FieldError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(FieldError::new(
            field,
            format!("must be a finite number, got {value}"),
        ))
    }
}

pub(crate) fn positive(field: &str, value: f64) -> Result<(), FieldError> {
    finite(field, value)?;
    if value > 0.0 {
        Ok(())
    } else {
        Err(FieldError::new(
            field,
            format!("must be positive, got {value}"),
        ))
    }
}

pub(crate) fn non_negative(field: &str, value: f64) -> Result<(), FieldError> {
    finite(field, value)?;
    if value >= 0.0 {
        Ok(())
    } else {
        Err(FieldError::new(
            field,
            format!("must not be negative, got {value}"),
        ))
    }
}

pub(crate) fn in_range(
    field: &str,
    value: f64,
    range: RangeInclusive<f64>,
) -> Result<(), FieldError> {
    finite(field, value)?;
    if range.contains(&value) {
        Ok(())
    } else {
        let (min, max) = range.into_inner();
        Err(FieldError::new(
            field,
            format!("must lie in [{min}, {max}], got {value}"),
        ))
    }
}

/// A length of a shape: positive, and within the engine's [MIN_EXTENT, MAX_EXTENT] m.
pub(crate) fn extent(field: &str, value: f64) -> Result<(), FieldError> {
    positive(field, value)?;
    if (MIN_EXTENT..=MAX_EXTENT).contains(&value) {
        Ok(())
    } else {
        Err(FieldError::new(
            field,
            format!("must lie in [{MIN_EXTENT}, {MAX_EXTENT}] m, got {value}"),
        ))
    }
}

/// Each component finite, named `field.x`, `field.y`, `field.z`.
pub(crate) fn vector(field: &str, value: DVec3) -> Result<(), FieldError> {
    finite(&format!("{field}.x"), value.x)?;
    finite(&format!("{field}.y"), value.y)?;
    finite(&format!("{field}.z"), value.z)
}
