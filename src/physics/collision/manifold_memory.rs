//! Manifold reuse: while two bodies move less than `REUSE_DISTANCE` relative to each other
//! since their manifold was generated, that manifold is carried along instead of generated
//! again.
//!
//! A remembered manifold keeps each contact's two surface points and its normal in the frames
//! of the bodies, as they were when it was generated. Carrying it places them with the
//! bodies' current poses and measures each separation again along the normal, so a resting
//! contact keeps its true depth. What can go stale is which features touch and where along
//! the surfaces, and no surface point has moved more than `REUSE_DISTANCE` against the other
//! body: a feature that was farther than the generation's margin cannot have reached the
//! other body yet. A pair that could close more than that margin in the coming step (a body
//! just struck) is generated again, so that its speculative contacts are all there.
//!
//! Why: in a pile or a stack most pairs barely move from one step to the next, and generating
//! their contacts (separating axes and clipping, or GJK and EPA for rounded shapes) costs
//! tens of times more than carrying them.
//!
//! A carried contact's impulses act where they acted when it was generated: its lever arms
//! from the two centres of mass stay as they were, in world axes, while its depth follows
//! the bodies. Re-measured arms follow the turn that the soft contacts' give lets a loaded
//! body make, which shifts the load over to the side it leans to: a column of 30 unit boxes
//! buckled under its own weight as a chain of such springs does, and kept arms hold it as
//! rigid blocks stand (BENCHMARKS.md, "Carried contacts keep their lever arms"). The arms
//! are off from the material points by at most `REUSE_DISTANCE`.

use glam::{DMat3, DVec3, Vec3};
use serde::{Deserialize, Serialize};
use smallvec::SmallVec;

use crate::physics::collision::contact::{
    Contact, ContactKind, ContactManifold, FeatureId, MAX_MANIFOLD_POINTS,
};
use crate::physics::collision::separating_axis::{
    ContactFeature, SeparatedPair, SeparatingFeature,
};
use crate::physics::collision::sorted_seek;
use crate::physics::dynamics::body::{BodyId, RigidBody};

/// How far, m, any surface point of one body may have moved against the other since their
/// manifold was generated for it to be carried. A tenth of the speculative distance, so that
/// nothing the generation left out can come into contact meanwhile. Carried contacts sit
/// where generated ones would to within this distance along the surfaces; their depths are
/// off by half its square over the radius of curvature at most (13 µm on a 15 cm radius).
/// It is larger than 1 mm because that regenerated many more of a landed pile's manifolds,
/// at no better accuracy (BENCHMARKS.md, "Manifold reuse distance").
pub const REUSE_DISTANCE: f64 = 2e-3;

/// One contact in the frames of its bodies.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
struct RememberedContact {
    /// The point on A's surface, in A's shape frame.
    on_a: DVec3,
    /// The point on B's surface, in B's shape frame.
    on_b: DVec3,
    /// The normal from A to B, in A's shape frame.
    normal: DVec3,
    kind: ContactKind,
    feature: FeatureId,
    /// The lever arms from A's and B's centres of mass, world axes, as generated
    /// (`Contact::levers`). Absent from snapshots written before they were kept: those
    /// contacts act where they are carried to.
    #[serde(default)]
    levers: Option<[Vec3; 2]>,
}

/// Where the two bodies stood relative to each other when the manifold was generated.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
struct RelativePose {
    /// B's orientation in A's frame.
    rotation: DMat3,
    /// B's shape origin in A's frame.
    b_in_a: DVec3,
    /// A's shape origin in B's frame.
    a_in_b: DVec3,
}

impl RelativePose {
    /// The pose of `b` against `a`, whose shape origins are `origin_a` and `origin_b`.
    fn of(a: &RigidBody, origin_a: DVec3, b: &RigidBody, origin_b: DVec3) -> Self {
        RelativePose {
            rotation: a.orientation.transpose() * b.orientation,
            b_in_a: a.orientation.transpose() * (origin_b - origin_a),
            a_in_b: b.orientation.transpose() * (origin_a - origin_b),
        }
    }

    /// An upper bound on how far any surface point of either body has moved against the
    /// other between `self` and `now`: a point at distance r from its shape origin moves by
    /// at most the rotation's chord times r plus the origin's move, seen from either body,
    /// and the smaller of the two bounds holds.
    fn displacement_bound(&self, now: &RelativePose, radius_a: f64, radius_b: f64) -> f64 {
        let r0 = &self.rotation;
        let r1 = &now.rotation;
        // trace(R1 R0ᵀ) = 1 + 2 cos θ, and the chord 2 sin(θ/2) is √(3 − trace).
        let trace = r1.x_axis.dot(r0.x_axis) + r1.y_axis.dot(r0.y_axis) + r1.z_axis.dot(r0.z_axis);
        let chord = (3.0 - trace).max(0.0).sqrt();
        let seen_from_a = chord * radius_b + (now.b_in_a - self.b_in_a).length();
        let seen_from_b = chord * radius_a + (now.a_in_b - self.a_in_b).length();
        seen_from_a.min(seen_from_b)
    }
}

/// A manifold as its two bodies saw it when it was generated.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RememberedManifold {
    pub body_a: BodyId,
    pub body_b: BodyId,
    pose: RelativePose,
    /// The margin it was generated with: every feature it left out was farther apart.
    margin: f64,
    contacts: SmallVec<[RememberedContact; MAX_MANIFOLD_POINTS]>,
    /// For two polyhedra, the feature the contacts were clipped from, tried first when the
    /// manifold cannot be carried (absent from snapshots written before it was kept).
    #[serde(default)]
    pub feature: Option<ContactFeature>,
}

impl RememberedManifold {
    /// `manifold`, just generated with `margin` for the bodies `a` and `b` in their current
    /// poses, from `feature` when they are polyhedra.
    pub fn of(
        manifold: &ContactManifold,
        a: &RigidBody,
        b: &RigidBody,
        margin: f64,
        feature: Option<ContactFeature>,
    ) -> Self {
        let to_a = a.orientation.transpose();
        let to_b = b.orientation.transpose();
        let (origin_a, origin_b) = (a.shape_origin(), b.shape_origin());
        let contacts = manifold.contacts.iter().map(|c| RememberedContact {
            on_a: to_a * (c.point_on_a() - origin_a),
            on_b: to_b * (c.point_on_b() - origin_b),
            normal: to_a * c.normal,
            kind: c.kind,
            feature: c.feature,
            levers: Some(c.lever_arms(a.position, b.position).map(|l| l.as_vec3())),
        });
        RememberedManifold {
            body_a: manifold.body_a,
            body_b: manifold.body_b,
            pose: RelativePose::of(a, origin_a, b, origin_b),
            margin,
            contacts: contacts.collect(),
            feature,
        }
    }

    /// The manifold carried to the bodies' current poses, keeping the contacts within
    /// `margin`; None when it must be generated again: the bodies have moved too far against
    /// each other for it, they can close more than what it left out in this step
    /// (`closable`, see `closing_speed`), or no contact is left. For tests: the
    /// narrow phase uses `carry_into`.
    #[cfg(test)]
    pub fn carried(
        &self,
        a: &RigidBody,
        b: &RigidBody,
        margin: f64,
        closable: f64,
    ) -> Option<ContactManifold> {
        let radii = [a.shape.bounding_radius(), b.shape.bounding_radius()];
        let mut carried = Vec::with_capacity(1);
        self.carry_into(a, b, radii, margin, closable, &mut carried);
        carried.pop()
    }

    /// `carried` pushed onto `manifolds` when there is one (true; see
    /// `ContactManifold::push_built`). `radii` are the shapes' bounding radii, which the
    /// caller has at hand.
    pub fn carry_into(
        &self,
        a: &RigidBody,
        b: &RigidBody,
        [radius_a, radius_b]: [f64; 2],
        margin: f64,
        closable: f64,
        manifolds: &mut Vec<ContactManifold>,
    ) -> bool {
        let (origin_a, origin_b) = (a.shape_origin(), b.shape_origin());
        let now = RelativePose::of(a, origin_a, b, origin_b);
        let moved = self.pose.displacement_bound(&now, radius_a, radius_b);
        // A non-finite pose or speed gives NaN, which is not within the bounds either.
        let within = moved <= REUSE_DISTANCE && closable < self.margin - REUSE_DISTANCE;
        if !within {
            return false;
        }
        ContactManifold::push_built(manifolds, self.body_a, self.body_b, |points| {
            for c in &self.contacts {
                let on_a = origin_a + a.orientation * c.on_a;
                let on_b = origin_b + b.orientation * c.on_b;
                let normal = a.orientation * c.normal;
                let separation = (on_b - on_a).dot(normal);
                if separation <= margin {
                    points.push(Contact {
                        position: 0.5 * (on_a + on_b),
                        normal,
                        separation,
                        kind: c.kind,
                        feature: c.feature,
                        time_of_impact: 0.0,
                        levers: c.levers,
                    });
                }
            }
            points.sort_by(|x, y| x.separation.total_cmp(&y.separation));
        })
    }

    fn is_finite(&self) -> bool {
        let pose = &self.pose;
        self.margin.is_finite()
            && self.feature.is_none_or(|f| f.separation.is_finite())
            && pose.rotation.is_finite()
            && pose.b_in_a.is_finite()
            && pose.a_in_b.is_finite()
            && (self.contacts.iter()).all(|c| {
                c.on_a.is_finite()
                    && c.on_b.is_finite()
                    && c.normal.is_finite()
                    && c.levers.is_none_or(|[a, b]| a.is_finite() && b.is_finite())
            })
    }

    /// Whether every kept lever arm lies within the margin of its body's bounding sphere,
    /// as a generated one does.
    fn levers_within_reach(&self, a: &RigidBody, b: &RigidBody) -> bool {
        let reach = |body: &RigidBody| {
            body.shape.bounding_radius() + body.local_center.length() + self.margin.abs()
        };
        let (reach_a, reach_b) = (reach(a), reach(b));
        let mut levers = self.contacts.iter().filter_map(|c| c.levers);
        levers.all(|[lever_a, lever_b]| {
            lever_a.as_dvec3().length() <= reach_a && lever_b.as_dvec3().length() <= reach_b
        })
    }
}

/// The manifolds of the last step, and the pairs of polyhedra a separating axis kept apart
/// (see `separating_axis`), each sorted by body pair as the narrow phase visits them.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ManifoldMemory {
    manifolds: Vec<RememberedManifold>,
    /// Absent from snapshots written before it was kept; it only spares searches.
    #[serde(default)]
    separated: Vec<SeparatedPair>,
}

/// What the narrow phase hands the memory after a step, and gets back to fill the next.
#[derive(Clone, Debug, Default)]
pub struct Remembered {
    pub manifolds: Vec<RememberedManifold>,
    pub separated: Vec<SeparatedPair>,
}

impl Remembered {
    pub fn clear(&mut self) {
        self.manifolds.clear();
        self.separated.clear();
    }

    pub fn append(&mut self, other: &mut Remembered) {
        self.manifolds.append(&mut other.manifolds);
        self.separated.append(&mut other.separated);
    }

    pub fn reserve(&mut self, pairs: usize) {
        self.manifolds.reserve(pairs);
        self.separated.reserve(pairs);
    }
}

impl ManifoldMemory {
    /// Both lists must come sorted by body pair (the narrow phase's order).
    pub fn new(
        Remembered {
            manifolds,
            separated,
        }: Remembered,
    ) -> Self {
        debug_assert!(manifolds.is_sorted_by_key(|m| (m.body_a, m.body_b)));
        debug_assert!(separated.is_sorted_by_key(|m| (m.body_a, m.body_b)));
        ManifoldMemory {
            manifolds,
            separated,
        }
    }

    /// Remembers `remembered` instead (sorted by body pair, as for `new`) and hands back
    /// the lists it held.
    pub fn replace(&mut self, remembered: Remembered) -> Remembered {
        let old = std::mem::replace(self, ManifoldMemory::new(remembered));
        Remembered {
            manifolds: old.manifolds,
            separated: old.separated,
        }
    }

    /// `find_from` with a cursor of its own (for tests: the narrow phase keeps one).
    #[cfg(test)]
    pub fn find(&self, a: BodyId, b: BodyId) -> Option<&RememberedManifold> {
        self.find_from(a, b, &mut 0)
    }

    /// `find`, starting where the last search left `cursor` (see `sorted_seek`): the
    /// narrow phase asks for its pairs in ascending order, so walking on from the last
    /// pair beats a binary search per pair (BENCHMARKS.md, "Seeking remembered manifolds").
    pub fn find_from(
        &self,
        a: BodyId,
        b: BodyId,
        cursor: &mut usize,
    ) -> Option<&RememberedManifold> {
        let key = |m: &RememberedManifold| (m.body_a, m.body_b);
        let at = sorted_seek::seek(&self.manifolds, key, &(a, b), cursor);
        self.manifolds.get(at).filter(|m| key(m) == (a, b))
    }

    /// The feature that separated `a` and `b` last step, if one did; searched from
    /// `cursor` as `find_from` does.
    pub fn separating_feature(
        &self,
        a: BodyId,
        b: BodyId,
        cursor: &mut usize,
    ) -> Option<SeparatingFeature> {
        let key = |m: &SeparatedPair| (m.body_a, m.body_b);
        let at = sorted_seek::seek(&self.separated, key, &(a, b), cursor);
        let found = self.separated.get(at).filter(|m| key(m) == (a, b));
        found.map(|m| m.feature)
    }

    /// Drops what was remembered about `bodies` (added, edited or removed since: their
    /// shapes may have changed).
    pub fn forget(&mut self, bodies: &[u32]) {
        let Some(&highest) = bodies.iter().max() else {
            return;
        };
        if self.manifolds.is_empty() && self.separated.is_empty() {
            return;
        }
        let mut marked = vec![false; highest as usize + 1];
        for &index in bodies {
            marked[index as usize] = true;
        }
        let forgotten = |id: BodyId| marked.get(id.index()).copied().unwrap_or(false);
        self.manifolds
            .retain(|m| !forgotten(m.body_a) && !forgotten(m.body_b));
        self.separated
            .retain(|m| !forgotten(m.body_a) && !forgotten(m.body_b));
    }

    pub fn clear(&mut self) {
        self.manifolds.clear();
        self.separated.clear();
    }

    /// What a snapshot's reader checks: sorted, finite, naming only `bodies`, with every
    /// kept lever arm within its body's reach.
    pub fn check(&self, bodies: &[RigidBody]) -> Result<(), String> {
        let count = bodies.len();
        if !(self.manifolds).is_sorted_by_key(|m| (m.body_a, m.body_b)) {
            return Err("the remembered manifolds are not sorted by body pair".into());
        }
        if !(self.separated).is_sorted_by_key(|m| (m.body_a, m.body_b)) {
            return Err("the separated pairs are not sorted by body pair".into());
        }
        if (self.separated.iter()).any(|m| m.body_a.index().max(m.body_b.index()) >= count) {
            return Err("a separated pair names a missing body".into());
        }
        for m in &self.manifolds {
            if m.body_a.index().max(m.body_b.index()) >= count {
                return Err("a remembered manifold names a missing body".into());
            }
            if !m.is_finite() {
                return Err(format!(
                    "the remembered manifold of bodies {} and {} is not finite",
                    m.body_a.0, m.body_b.0
                ));
            }
            if !m.levers_within_reach(&bodies[m.body_a.index()], &bodies[m.body_b.index()]) {
                return Err(format!(
                    "the remembered manifold of bodies {} and {} has a lever arm beyond its body",
                    m.body_a.0, m.body_b.0
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use glam::DQuat;
    use proptest::prelude::*;

    use super::*;
    use crate::physics::collision::manifold::contact_manifold;
    use crate::physics::collision::manifold::tests::unit_quat;
    use crate::physics::dynamics::body::BodyDesc;
    use crate::physics::geometry::shape::Shape;

    fn body(desc: BodyDesc) -> RigidBody {
        RigidBody::from_desc(&desc).unwrap()
    }

    fn floor() -> RigidBody {
        body(
            BodyDesc::fixed(Shape::cuboid(DVec3::new(5.0, 0.5, 5.0)))
                .at(DVec3::new(0.0, -0.5, 0.0)),
        )
    }

    fn generated(a: &RigidBody, b: &RigidBody) -> ContactManifold {
        contact_manifold(a, BodyId(0), b, BodyId(1), 0.02).expect("they touch")
    }

    /// Searched from a cursor, in ascending order, in any order and for pairs it does not
    /// hold, the memory finds what a binary search finds.
    #[test]
    fn searching_from_a_cursor_finds_what_a_binary_search_finds() {
        let (a, b) = (
            floor(),
            body(BodyDesc::dynamic(Shape::sphere(0.5)).at(DVec3::Y * 0.49)),
        );
        let one = RememberedManifold::of(&generated(&a, &b), &a, &b, 0.02, None);
        // Pairs (i, j) for i < 30 and every third j above it.
        let keys: Vec<(u32, u32)> = (0..30)
            .flat_map(|i| (i + 1..40).filter(|j| j % 3 == 0).map(move |j| (i, j)))
            .collect();
        let manifolds = (keys.iter())
            .map(|&(i, j)| RememberedManifold {
                body_a: BodyId(i),
                body_b: BodyId(j),
                ..one.clone()
            })
            .collect();
        let memory = ManifoldMemory::new(Remembered {
            manifolds,
            separated: Vec::new(),
        });
        let binary = |a: u32, b: u32| {
            let found = keys.binary_search(&(a, b)).ok();
            found.map(|k| (memory.manifolds[k].body_a, memory.manifolds[k].body_b))
        };
        // Every pair below 40 in ascending order, then a scrambled order, with one cursor.
        let ascending = (0..40).flat_map(|i| (i + 1..40).map(move |j| (i, j)));
        let scrambled = (0..1000u32).map(|k| ((k * 7919) % 40, (k * 104_729) % 40));
        let mut cursor = 0;
        for (i, j) in ascending.chain(scrambled) {
            let found = memory.find_from(BodyId(i), BodyId(j), &mut cursor);
            assert_eq!(
                found.map(|m| (m.body_a, m.body_b)),
                binary(i, j),
                "({i}, {j})"
            );
        }
    }

    /// `b` moved by `offset` and turned by `turn` (applied about its position).
    fn moved(b: &RigidBody, offset: DVec3, turn: DQuat) -> RigidBody {
        let mut moved = b.clone();
        moved.position += offset;
        moved.orientation = DMat3::from_quat(turn) * moved.orientation;
        moved
    }

    /// The carried manifold has the generated one's contacts, at its separations to within
    /// `tolerance` and its positions to within the reuse distance; it keeps the lever arms
    /// they were generated with, which are within the reuse distance of the fresh ones.
    fn assert_carried_matches_generated(
        a: &RigidBody,
        b: &RigidBody,
        b_now: &RigidBody,
        tolerance: f64,
    ) {
        let original = generated(a, b);
        let remembered = RememberedManifold::of(&original, a, b, 0.02, None);
        let carried = remembered
            .carried(a, b_now, 0.02, 0.0)
            .expect("close enough to carry");
        let fresh = generated(a, b_now);
        assert_eq!(carried.contacts.len(), fresh.contacts.len());
        for c in &carried.contacts {
            let same = (fresh.contacts.iter())
                .find(|f| f.feature == c.feature)
                .expect("the same features touch");
            assert!(
                (c.separation - same.separation).abs() < tolerance,
                "{c:?} against {same:?}"
            );
            assert!(c.position.distance(same.position) <= REUSE_DISTANCE);
            assert!(c.normal.distance(same.normal) < 1e-3);
            let kept = (original.contacts.iter())
                .find(|o| o.feature == c.feature)
                .expect("carried from the generated contacts");
            let levers = [kept.position - a.position, kept.position - b.position];
            assert_eq!(c.levers, Some(levers.map(|l| l.as_vec3())));
            assert_eq!(same.levers, None, "a generated contact acts where it is");
            assert!(levers[0].distance(same.position - a.position) <= REUSE_DISTANCE);
            assert!(levers[1].distance(same.position - b_now.position) <= REUSE_DISTANCE);
        }
    }

    #[test]
    fn a_resting_box_nudged_carries_the_contacts_generation_finds() {
        let a = floor();
        let b = body(
            BodyDesc::dynamic(Shape::cuboid(DVec3::splat(0.5)))
                .at(DVec3::new(0.3, 0.498, -0.2))
                .rotated(DQuat::from_rotation_y(0.4)),
        );
        // Bound: 1.37 mm of translation plus 0.6 mrad times the corner radius 0.87 m.
        let turn = DQuat::from_axis_angle(DVec3::new(1.0, 0.2, -0.5).normalize(), 6e-4);
        let b_now = moved(&b, DVec3::new(1e-3, -8e-4, 5e-4), turn);
        // Vertex on face: the depth is exact but for the normal's turn times the slide.
        assert_carried_matches_generated(&a, &b, &b_now, 1e-8);
    }

    /// On a curved surface the remembered point rolls off the lowest one: the depth is off by
    /// d²/2r at most, d the reuse distance and r the smaller radius here (0.15 m).
    #[test]
    fn a_resting_sphere_and_lying_cylinder_nudged_carry_their_contacts() {
        let tolerance = REUSE_DISTANCE * REUSE_DISTANCE / (2.0 * 0.15);
        let a = floor();
        let offset = DVec3::new(-8e-4, 6e-4, 5e-4);
        let sphere = body(BodyDesc::dynamic(Shape::sphere(0.3)).at(DVec3::new(0.0, 0.299, 0.0)));
        let spin = DQuat::from_rotation_z(1e-3);
        assert_carried_matches_generated(&a, &sphere, &moved(&sphere, offset, spin), tolerance);
        let cylinder = body(
            BodyDesc::dynamic(Shape::Cylinder {
                half_height: 0.2,
                radius: 0.15,
            })
            .at(DVec3::new(1.0, 0.149, 0.5))
            .rotated(DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2)),
        );
        let roll = DQuat::from_rotation_y(1e-3);
        assert_carried_matches_generated(&a, &cylinder, &moved(&cylinder, offset, roll), tolerance);
    }

    #[test]
    fn a_pair_that_moved_more_than_the_reuse_distance_is_generated_again() {
        let a = floor();
        let b = body(
            BodyDesc::dynamic(Shape::cuboid(DVec3::splat(0.5))).at(DVec3::new(0.0, 0.499, 0.0)),
        );
        let remembered = RememberedManifold::of(&generated(&a, &b), &a, &b, 0.02, None);
        let slid = moved(&b, DVec3::new(2.5e-3, 0.0, 0.0), DQuat::IDENTITY);
        assert!(remembered.carried(&a, &slid, 0.02, 0.0).is_none());
        // 3 mrad turns the corners, 0.87 m out, by 2.6 mm.
        let turned = moved(&b, DVec3::ZERO, DQuat::from_rotation_y(3e-3));
        assert!(remembered.carried(&a, &turned, 0.02, 0.0).is_none());
        // Lifted from 1 mm deep to 0.2 mm deep, within the reuse distance: with a margin of
        // -0.5 mm no contact is left to carry.
        let lifted = moved(&b, DVec3::new(0.0, 0.8e-3, 0.0), DQuat::IDENTITY);
        assert!(remembered.carried(&a, &lifted, 0.0, 0.0).is_some());
        assert!(remembered.carried(&a, &lifted, -0.5e-3, 0.0).is_none());
        // Struck, not yet moved: in this step it could close more than the 2 cm the
        // generation looked out to, less the reuse distance, so a corner left out could
        // reach the floor.
        assert!(remembered.carried(&a, &b, 0.02, 0.017).is_some());
        assert!(remembered.carried(&a, &b, 0.04, 0.02).is_none());
    }

    #[test]
    fn the_memory_forgets_edited_bodies_and_checks_what_a_snapshot_holds() {
        let a = floor();
        let b = body(BodyDesc::dynamic(Shape::sphere(0.3)).at(DVec3::new(0.0, 0.299, 0.0)));
        let remembered = |x: u32, y: u32| RememberedManifold {
            body_a: BodyId(x),
            body_b: BodyId(y),
            ..RememberedManifold::of(&generated(&a, &b), &a, &b, 0.02, None)
        };
        let mut memory = ManifoldMemory::new(Remembered {
            manifolds: vec![remembered(0, 1), remembered(0, 2), remembered(1, 3)],
            separated: Vec::new(),
        });
        let bodies = [a.clone(), a.clone(), b.clone(), b.clone()];
        assert_eq!(memory.check(&bodies), Ok(()));
        assert!(
            memory
                .check(&bodies[..3])
                .unwrap_err()
                .contains("missing body")
        );
        let mut far = memory.clone();
        far.manifolds[1].contacts[0].levers = Some([Vec3::ZERO, Vec3::X * 0.4]);
        let refused = far.check(&bodies).unwrap_err();
        assert!(refused.contains("bodies 0 and 2 has a lever arm beyond its body"));
        memory.forget(&[2]);
        assert!(memory.find(BodyId(0), BodyId(2)).is_none());
        assert!(memory.find(BodyId(0), BodyId(1)).is_some());
        assert!(memory.find(BodyId(1), BodyId(3)).is_some());
        memory.manifolds[0].pose.b_in_a.x = f64::NAN;
        assert!(memory.check(&bodies).unwrap_err().contains("not finite"));
        memory.manifolds.swap(0, 1);
        assert!(memory.check(&bodies).unwrap_err().contains("not sorted"));
    }

    fn small_vector(size: f64) -> impl Strategy<Value = DVec3> {
        (-size..size, -size..size, -size..size).prop_map(|(x, y, z)| DVec3::new(x, y, z))
    }

    fn corners(b: &RigidBody, half: DVec3) -> Vec<DVec3> {
        (0..8)
            .map(|k| {
                let sign = |bit: i32| if k & (1 << bit) == 0 { -1.0 } else { 1.0 };
                let local = half * DVec3::new(sign(0), sign(1), sign(2));
                b.shape_origin() + b.orientation * local
            })
            .collect()
    }

    proptest! {
        /// No two surface points of the pair (here: any corner of one box against any of the
        /// other, the points farthest from their origins) changed their distance by more than
        /// the displacement bound, however both bodies moved.
        #[test]
        fn the_displacement_bound_holds_for_every_pair_of_surface_points(
            half_a in small_vector(2.0), half_b in small_vector(2.0),
            turn_a in unit_quat(), turn_b in unit_quat(), offset in small_vector(3.0),
            move_a in small_vector(0.01), move_b in small_vector(0.01),
            spin_a in small_vector(0.01), spin_b in small_vector(0.01),
        ) {
            let (half_a, half_b) = (half_a.abs() + 0.05, half_b.abs() + 0.05);
            let a = body(BodyDesc::dynamic(Shape::cuboid(half_a)).rotated(turn_a));
            let b = body(BodyDesc::dynamic(Shape::cuboid(half_b)).at(offset).rotated(turn_b));
            let a_now = moved(&a, move_a, DQuat::from_scaled_axis(spin_a));
            let b_now = moved(&b, move_b, DQuat::from_scaled_axis(spin_b));
            let pose = |a: &RigidBody, b: &RigidBody| {
                RelativePose::of(a, a.shape_origin(), b, b.shape_origin())
            };
            let bound = pose(&a, &b).displacement_bound(
                &pose(&a_now, &b_now),
                a.shape.bounding_radius(),
                b.shape.bounding_radius(),
            );
            let (then_a, then_b) = (corners(&a, half_a), corners(&b, half_b));
            let (now_a, now_b) = (corners(&a_now, half_a), corners(&b_now, half_b));
            for i in 0..8 {
                for j in 0..8 {
                    let change = (now_a[i].distance(now_b[j]) - then_a[i].distance(then_b[j])).abs();
                    prop_assert!(change <= bound * (1.0 + 1e-9) + 1e-12, "{change} > {bound}");
                }
            }
        }
    }
}
