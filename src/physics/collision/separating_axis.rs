//! The separating axis a pair of polyhedra was last found apart by, tried first the next
//! step.
//!
//! Two bodies near each other in a pile or a rain are mostly apart, and stay apart by the
//! same face or edge pair from one step to the next. Measuring the gap along that one axis
//! costs a support query per shape, where the full search visits every face and edge pair.
//! The check is sound whatever the bodies did meanwhile: the gap along any axis, measured
//! with the exact support functions, is a lower bound on the distance, so a pair it finds
//! farther apart than the margin has no contact, as the full search would have found.
//!
//! A touching pair remembers the feature its contacts were clipped from instead
//! (`ContactFeature`, kept with its manifold), and is clipped from it again without a search
//! while the separation along it stays near what the last full search measured
//! (`manifold::FEATURE_TOLERANCE`).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::physics::collision::manifold::{BOX_EDGES, BOX_FACES};
use crate::physics::dynamics::body::BodyId;
use crate::physics::geometry::gjk::{PosedShape, SupportMap};
use crate::physics::geometry::shape::Shape;

/// The features whose axis separated a pair, by their indices in the shapes' face and edge
/// lists (those of `ConvexHull`, or of the contact search's box tables).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum SeparatingFeature {
    /// The normal of a face of A.
    FaceOfA(u32),
    /// The normal of a face of B, turned to point from A to B.
    FaceOfB(u32),
    /// The cross product of an edge of A and an edge of B.
    Edges(u32, u32),
}

impl SeparatingFeature {
    /// Whether `a` and `b` are farther apart than `margin` along this feature's axis in
    /// their current poses. False when the shapes have no such feature (not polyhedra, or
    /// an index out of range: a stale or hand-edited memory) or the edges are parallel.
    pub fn still_separates(self, a: &PosedShape, b: &PosedShape, margin: f64) -> bool {
        let Some(gap) = self.gap(a, b) else {
            return false;
        };
        // The full search rounds differently: a gap this close to the margin is left to it.
        let scale = a.origin.length() + b.origin.length();
        let slack = ROUND_OFF * (scale + a.shape.bounding_radius() + b.shape.bounding_radius());
        gap > margin + slack
    }

    /// A lower bound on the gap between the shapes along this feature's axis. Along a face's
    /// normal its own shape reaches no farther than the face's plane (and a valid hull's
    /// tolerance above it), so only the other shape's support is sought.
    fn gap(self, a: &PosedShape, b: &PosedShape) -> Option<f64> {
        let facing = |owner: &PosedShape, other: &PosedShape, k: u32| {
            let (normal, reach) = face_plane(owner.shape, k)?;
            let normal = owner.rotation * normal;
            let plane = normal.dot(owner.origin) + reach;
            Some(normal.dot(other.core_support(-normal)) - plane)
        };
        match self {
            SeparatingFeature::FaceOfA(k) => facing(a, b, k),
            SeparatingFeature::FaceOfB(k) => facing(b, a, k),
            SeparatingFeature::Edges(..) => {
                let axis = self.axis(a, b)?;
                Some(axis.dot(b.core_support(-axis)) - axis.dot(a.core_support(axis)))
            }
        }
    }

    /// The unit axis, pointing from A towards B.
    fn axis(self, a: &PosedShape, b: &PosedShape) -> Option<DVec3> {
        match self {
            SeparatingFeature::FaceOfA(k) => Some(a.rotation * face_normal(a.shape, k)?),
            SeparatingFeature::FaceOfB(k) => Some(-(b.rotation * face_normal(b.shape, k)?)),
            SeparatingFeature::Edges(i, j) => {
                let along_a = a.rotation * edge_direction(a.shape, i)?;
                let along_b = b.rotation * edge_direction(b.shape, j)?;
                let cross = along_a.cross(along_b);
                let length = cross.length();
                if length <= PARALLEL * along_a.length() * along_b.length() {
                    return None;
                }
                let axis = cross / length;
                let towards_b = world_center(b) - world_center(a);
                Some(if axis.dot(towards_b) < 0.0 {
                    -axis
                } else {
                    axis
                })
            }
        }
    }
}

/// The feature of two polyhedra their contacts were clipped from by a full search, with the
/// separation along its axis then (negative: overlapping), m.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactFeature {
    pub feature: SeparatingFeature,
    pub separation: f64,
}

/// Relative round-off allowed between this check and the full search, over the distances
/// from the origin involved: far above round-off, far below any gap that matters.
const ROUND_OFF: f64 = 1e-9;

/// Below this sine of their angle, two edges are parallel and make no axis (as in the full
/// search, where the face axes cover them).
const PARALLEL: f64 = 1e-9;

/// A pair of bodies and the feature that last separated them.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SeparatedPair {
    pub body_a: BodyId,
    pub body_b: BodyId,
    pub feature: SeparatingFeature,
}

/// The middle of the shape's bounds, in the world: inside it, which orients an edge axis.
fn world_center(posed: &PosedShape) -> DVec3 {
    match posed.shape {
        Shape::ConvexHull(hull) => {
            let (min, max) = hull.bounds();
            posed.origin + posed.rotation * (0.5 * (min + max))
        }
        _ => posed.origin,
    }
}

/// Face `k`'s outward unit normal in shape coordinates.
fn face_normal(shape: &Shape, k: u32) -> Option<DVec3> {
    face_plane(shape, k).map(|(normal, _)| normal)
}

/// Face `k`'s outward unit normal in shape coordinates, and how far the shape reaches from
/// its origin along it, at most.
fn face_plane(shape: &Shape, k: u32) -> Option<(DVec3, f64)> {
    let k = k as usize;
    match shape {
        Shape::Cuboid { half_extents } => {
            let normal = BOX_FACES.get(k)?.1;
            Some((normal, normal.abs().dot(*half_extents)))
        }
        Shape::ConvexHull(hull) => {
            let face = hull.faces.get(k)?;
            Some((face.normal, face.offset + hull.plane_tolerance()))
        }
        _ => None,
    }
}

/// Edge `k`'s direction in shape coordinates (not of unit length).
fn edge_direction(shape: &Shape, k: u32) -> Option<DVec3> {
    let k = k as usize;
    match shape {
        Shape::Cuboid { half_extents } => {
            let [start, end] = BOX_EDGES.get(k)?.map(|i| box_corner(*half_extents, i));
            Some(end - start)
        }
        Shape::ConvexHull(hull) => {
            let [start, end] = hull.edges.get(k)?.map(|i| hull.vertices.get(i as usize));
            Some(*end? - *start?)
        }
        _ => None,
    }
}

/// Corner `i` of a box: bit k of `i` chooses the sign along axis k, as the box tables number
/// them.
fn box_corner(half_extents: DVec3, i: u32) -> DVec3 {
    let sign = |k: u32| if i & (1 << k) == 0 { -1.0 } else { 1.0 };
    half_extents * DVec3::new(sign(0), sign(1), sign(2))
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use glam::DMat3;
    use proptest::prelude::*;

    use super::*;
    use crate::physics::collision::contact::ManifoldPoints;
    use crate::physics::collision::manifold::tests::unit_quat;
    use crate::physics::collision::manifold::{
        PairFeature, add_manifold_points, generate_contacts,
    };
    use crate::physics::geometry::epa::signed_distance;
    use crate::physics::geometry::hull::ConvexHull;

    /// A box, or a hull of 4 to 24 random points within 1 m of its origin.
    fn polyhedron() -> impl Strategy<Value = Shape> {
        let point = (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64);
        let hull = proptest::collection::vec(point, 4..24).prop_filter_map("a solid", |points| {
            let points: Vec<DVec3> = points
                .iter()
                .map(|&(x, y, z)| DVec3::new(x, y, z))
                .collect();
            let hull = ConvexHull::from_points(&points).ok()?;
            (hull.volume() > 1e-3).then(|| Shape::ConvexHull(Arc::new(hull)))
        });
        let cuboid = (0.05..1.0f64, 0.05..1.0f64, 0.05..1.0f64)
            .prop_map(|(x, y, z)| Shape::cuboid(DVec3::new(x, y, z)));
        prop_oneof![hull, cuboid]
    }

    /// Face and edge counts and two more, so that some features drawn are out of range.
    fn counts(shape: &Shape) -> (u32, u32) {
        match shape {
            Shape::ConvexHull(hull) => (hull.faces.len() as u32 + 2, hull.edges.len() as u32 + 2),
            _ => (8, 14),
        }
    }

    fn gap_along(feature: SeparatingFeature, a: &PosedShape, b: &PosedShape) -> f64 {
        let axis = feature
            .axis(a, b)
            .expect("the search's feature has an axis");
        axis.dot(b.core_support(-axis)) - axis.dot(a.core_support(axis))
    }

    /// Along a face's normal the bound from the face's plane lies within the plane
    /// tolerance below the gap measured from both shapes' supports, never above it.
    #[test]
    fn the_gap_from_a_face_plane_bounds_the_gap_from_the_supports() {
        let points: Vec<DVec3> = (0..32)
            .map(|k| {
                let t = k as f64;
                DVec3::new((1.3 * t).sin(), (0.7 * t).cos(), (2.9 * t).sin()).normalize()
            })
            .collect();
        let hull = Shape::ConvexHull(Arc::new(ConvexHull::from_points(&points).unwrap()));
        let cuboid = Shape::cuboid(DVec3::new(0.3, 0.5, 0.7));
        let turn = DMat3::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 0.4);
        for (shape_a, shape_b) in [(&hull, &cuboid), (&cuboid, &hull), (&hull, &hull)] {
            let a = PosedShape::new(shape_a, DVec3::new(0.2, 0.1, -0.3), turn);
            let b = PosedShape::new(shape_b, DVec3::new(1.9, 2.3, 0.8), turn.transpose());
            let faces = |shape: &Shape| match shape {
                Shape::ConvexHull(hull) => hull.faces.len() as u32,
                _ => 6,
            };
            let of_a = (0..faces(shape_a)).map(SeparatingFeature::FaceOfA);
            for feature in of_a.chain((0..faces(shape_b)).map(SeparatingFeature::FaceOfB)) {
                let bound = feature.gap(&a, &b).expect("a face");
                let measured = gap_along(feature, &a, &b);
                assert!(
                    bound <= measured + 1e-12,
                    "{feature:?}: {bound} above {measured}"
                );
                assert!(
                    bound >= measured - 1e-8,
                    "{feature:?}: {bound} far below {measured}"
                );
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(400))]

        /// Whatever feature it is given, in range or not, the check never calls a pair apart
        /// that the full search gives contacts, or whose distance (GJK/EPA) is within the
        /// margin; and the feature the full search finds a pair apart by holds them as far
        /// apart as the search found, and is found again at the same poses.
        #[test]
        fn a_pair_the_check_calls_apart_has_no_contact(
            shape_a in polyhedron(),
            shape_b in polyhedron(),
            turn_a in unit_quat(),
            turn_b in unit_quat(),
            offset in (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64),
            margin in 0.0..0.1f64,
            pick in 0..1000u32,
        ) {
            let a = PosedShape::new(&shape_a, DVec3::new(0.3, -0.2, 0.1), DMat3::from_quat(turn_a));
            let b_origin = DVec3::new(offset.0, offset.1, offset.2);
            let b = PosedShape::new(&shape_b, b_origin, DMat3::from_quat(turn_b));
            let contacts = generate_contacts(&a, &b, margin);
            let distance = signed_distance(&a, &b).distance;
            let ((faces_a, edges_a), (faces_b, edges_b)) = (counts(&shape_a), counts(&shape_b));
            let features = [
                SeparatingFeature::FaceOfA(pick % faces_a),
                SeparatingFeature::FaceOfB(pick % faces_b),
                SeparatingFeature::Edges(pick % edges_a, (pick / 7) % edges_b),
            ];
            for feature in features {
                if feature.still_separates(&a, &b, margin) {
                    prop_assert!(contacts.is_empty(), "{:?}: {} contacts", feature, contacts.len());
                    prop_assert!(distance > margin, "{:?}: distance {} within {}", feature, distance, margin);
                }
            }
            let mut points = ManifoldPoints::new();
            if let Some(PairFeature::Apart(found)) =
                add_manifold_points(&a, &b, margin, None, &mut points)
            {
                prop_assert!(points.is_empty());
                let gap = gap_along(found, &a, &b);
                prop_assert!(gap > margin - 1e-9, "{:?}: gap {} within {}", found, gap, margin);
                prop_assert!(
                    found.still_separates(&a, &b, margin) || gap - margin < 1e-6,
                    "{:?} separates by {} beyond the margin, but not when checked", found, gap - margin
                );
            }
        }
    }
}
