//! Convex hulls built from point clouds (quickhull), with polygonal faces and exact mass
//! properties from polyhedral volume integrals.

use glam::DVec3;
use thiserror::Error;

use crate::physics::mass::MassProperties;

/// A face of a hull: a convex polygon with its outward plane `normal · x = offset`.
#[derive(Clone, Debug, PartialEq)]
pub struct HullFace {
    /// Indices into `ConvexHull::vertices`, counter-clockwise seen from outside.
    pub vertices: Vec<u32>,
    pub normal: DVec3,
    pub offset: f64,
}

/// A closed convex polyhedron. Coplanar triangles are merged, so a box has 6 quad faces.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvexHull {
    pub vertices: Vec<DVec3>,
    pub faces: Vec<HullFace>,
    /// Each undirected edge once, as (lower index, higher index).
    pub edges: Vec<[u32; 2]>,
}

#[derive(Debug, Error, PartialEq)]
pub enum HullError {
    #[error("needs at least 4 points, got {0}")]
    TooFewPoints(usize),
    #[error("point {0} is not finite")]
    NotFinite(usize),
    #[error("points are degenerate: {0}")]
    Degenerate(&'static str),
}

impl ConvexHull {
    pub fn from_points(_points: &[DVec3]) -> Result<Self, HullError> {
        todo!("quickhull")
    }

    pub fn validate(&self) -> Result<(), HullError> {
        todo!()
    }

    pub fn support(&self, direction: DVec3) -> DVec3 {
        self.vertices
            .iter()
            .copied()
            .max_by(|a, b| a.dot(direction).total_cmp(&b.dot(direction)))
            .unwrap_or(DVec3::ZERO)
    }

    pub fn mass_properties(&self, _density: f64) -> MassProperties {
        todo!("polyhedral volume integrals")
    }
}
