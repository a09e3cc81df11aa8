//! `ShapeSpec` → engine `Shape`, checking every dimension and naming it by its path in the
//! file (`half_extents.x`, `parts[2].shape.radius`, `points[7].y`).

use std::sync::Arc;

use glam::DQuat;

use crate::physics::geometry::shape::MAX_EXTENT;
use crate::physics::{Compound, CompoundPart, MAX_COMPOUND_PARTS, Pose, Shape};
use crate::scene::error::FieldError;
use crate::scene::file::{PartSpec, Rotation, ShapeSpec};
use crate::scene::validate::{extent, finite, vector};

pub(crate) fn build_shape(spec: &ShapeSpec) -> Result<Shape, FieldError> {
    match spec {
        ShapeSpec::Sphere { radius } => {
            extent("radius", *radius)?;
            Ok(Shape::sphere(*radius))
        }
        ShapeSpec::Cuboid { half_extents } => {
            extent("half_extents.x", half_extents.x)?;
            extent("half_extents.y", half_extents.y)?;
            extent("half_extents.z", half_extents.z)?;
            Ok(Shape::cuboid(*half_extents))
        }
        ShapeSpec::Capsule {
            half_height,
            radius,
        } => {
            extent("half_height", *half_height)?;
            extent("radius", *radius)?;
            Ok(Shape::capsule(*half_height, *radius))
        }
        ShapeSpec::Cylinder {
            half_height,
            radius,
        } => {
            extent("half_height", *half_height)?;
            extent("radius", *radius)?;
            Ok(Shape::cylinder(*half_height, *radius))
        }
        ShapeSpec::Hull { points } => build_hull(points),
        ShapeSpec::Compound { parts } => build_compound(parts),
    }
}

fn build_hull(points: &[glam::DVec3]) -> Result<Shape, FieldError> {
    for (index, point) in points.iter().enumerate() {
        let field = format!("points[{index}]");
        vector(&field, *point)?;
        if point.abs().max_element() > MAX_EXTENT {
            return Err(FieldError::new(
                field,
                format!("must lie within {MAX_EXTENT} m of the origin, got {point}"),
            ));
        }
    }
    Shape::hull(points).map_err(|error| FieldError::new("points", error.to_string()))
}

fn build_compound(parts: &[PartSpec]) -> Result<Shape, FieldError> {
    if parts.is_empty() {
        return Err(FieldError::new("parts", "must hold at least one part"));
    }
    // Refused before any part is built.
    if parts.len() > MAX_COMPOUND_PARTS {
        let count = parts.len();
        let message = format!("{count} parts, more than MAX_COMPOUND_PARTS ({MAX_COMPOUND_PARTS})");
        return Err(FieldError::new("parts", message));
    }
    let parts = parts
        .iter()
        .enumerate()
        .map(|(index, part)| build_part(part).map_err(|e| e.within(&format!("parts[{index}]"))))
        .collect::<Result<Vec<_>, _>>()?;
    let compound =
        Compound::new(parts).map_err(|error| FieldError::new("parts", error.to_string()))?;
    Ok(Shape::Compound(Arc::new(compound)))
}

fn build_part(part: &PartSpec) -> Result<CompoundPart, FieldError> {
    if matches!(part.shape, ShapeSpec::Compound { .. }) {
        return Err(FieldError::new(
            "shape",
            "a compound part must be convex, not a compound",
        ));
    }
    let shape = build_shape(&part.shape).map_err(|e| e.within("shape"))?;
    vector("position", part.position)?;
    let rotation = build_rotation(&part.rotation).map_err(|e| e.within("rotation"))?;
    Ok(CompoundPart {
        pose: Pose::new(part.position, rotation),
        shape,
    })
}

pub(crate) fn build_rotation(rotation: &Rotation) -> Result<DQuat, FieldError> {
    match *rotation {
        Rotation::Euler(x, y, z) => {
            finite("x", x)?;
            finite("y", y)?;
            finite("z", z)?;
            Ok(DQuat::from_rotation_z(z.to_radians())
                * DQuat::from_rotation_y(y.to_radians())
                * DQuat::from_rotation_x(x.to_radians()))
        }
        Rotation::AxisAngle { axis, degrees } => {
            vector("axis", axis)?;
            finite("degrees", degrees)?;
            let unit = axis
                .try_normalize()
                .ok_or_else(|| FieldError::new("axis", "must not be the zero vector"))?;
            Ok(DQuat::from_axis_angle(unit, degrees.to_radians()))
        }
    }
}
