//! Concave bodies as a set of convex parts, each placed by a pose in the body's shape frame.

use glam::{DMat3, DVec3};
use serde::{Deserialize, Serialize};

use crate::physics::geometry::mass::{MassProperties, parallel_axis_term};
use crate::physics::geometry::shape::{Pose, Shape, ShapeError};

/// One convex part of a compound.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CompoundPart {
    /// Where the part's own shape frame sits in the compound's shape frame.
    pub pose: Pose,
    /// A convex shape: compounds do not nest.
    pub shape: Shape,
}

/// Most parts a compound may have. Contacts between two compounds test part against part,
/// so their cost grows with the product of the counts: two compounds of 3 000 parts took
/// 0.75 s a step, two of this many take about a hundredth of that.
pub const MAX_COMPOUND_PARTS: usize = 256;

/// A concave shape as a union of convex parts in one shape frame. GJK on it sees the convex
/// hull of the parts; contact generation and casts go through the parts one by one.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Compound {
    /// The parts: 1 to `MAX_COMPOUND_PARTS`, and none itself a compound (see `validate`).
    pub parts: Vec<CompoundPart>,
}

impl Compound {
    /// The compound of `parts`, if it passes `validate`.
    pub fn new(parts: Vec<CompoundPart>) -> Result<Self, ShapeError> {
        let compound = Compound { parts };
        compound.validate()?;
        Ok(compound)
    }

    /// Checks that there are 1 to `MAX_COMPOUND_PARTS` parts and that every part is convex,
    /// has a finite pose and a valid shape; the error names the first part that fails.
    pub fn validate(&self) -> Result<(), ShapeError> {
        if self.parts.is_empty() {
            return Err(ShapeError::Compound("has no parts".into()));
        }
        if self.parts.len() > MAX_COMPOUND_PARTS {
            return Err(ShapeError::TooManyParts(self.parts.len()));
        }
        for (index, part) in self.parts.iter().enumerate() {
            if !part.shape.is_convex() {
                return Err(ShapeError::Compound(format!(
                    "part {index} is itself a compound; parts must be convex"
                )));
            }
            let t = part.pose.translation;
            if !t.is_finite() || !part.pose.rotation.is_finite() {
                return Err(ShapeError::Compound(format!(
                    "part {index} has a non-finite pose"
                )));
            }
            part.shape.validate().map_err(|error| {
                ShapeError::Compound(format!(
                    "part {index} ({}): {error}",
                    part.shape.kind_name()
                ))
            })?;
        }
        Ok(())
    }

    /// Support of the convex hull of all parts.
    pub fn support(&self, direction: DVec3) -> DVec3 {
        self.parts
            .iter()
            .map(|part| {
                let local_dir = part.pose.rotation.inverse() * direction;
                part.pose.transform_point(part.shape.support(local_dir))
            })
            .max_by(|a, b| a.dot(direction).total_cmp(&b.dot(direction)))
            .unwrap_or(DVec3::ZERO)
    }

    /// Parts are treated as disjoint: overlapping parts count their shared volume twice.
    pub fn mass_properties(&self, density: f64) -> MassProperties {
        let parts: Vec<(MassProperties, Pose)> = self
            .parts
            .iter()
            .map(|part| (MassProperties::of_shape(&part.shape, density), part.pose))
            .collect();
        let mass: f64 = parts.iter().map(|(props, _)| props.mass).sum();
        let center = parts
            .iter()
            .map(|(props, pose)| pose.transform_point(props.center) * props.mass)
            .sum::<DVec3>()
            / mass;
        let inertia = parts
            .iter()
            .map(|(props, pose)| {
                let rotation = DMat3::from_quat(pose.rotation);
                let rotated = rotation * props.inertia * rotation.transpose();
                let offset = pose.transform_point(props.center) - center;
                rotated + parallel_axis_term(props.mass, offset)
            })
            .fold(DMat3::ZERO, |sum, term| sum + term);
        MassProperties {
            mass,
            center,
            inertia,
        }
    }
}
