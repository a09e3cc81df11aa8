//! Contact data shared by the narrow phase, time of impact and the solvers. Plain data only.
//!
//! Conventions used everywhere in the engine:
//! - the normal is a unit vector pointing from body A towards body B;
//! - `separation` is the signed distance between the surfaces along the normal: positive when
//!   apart, negative when they penetrate;
//! - `position` is the midpoint between the two surface points, so the point on A is
//!   `position - normal * separation / 2` and the point on B is `position + normal * separation / 2`.

use glam::{DVec3, Vec3};
use serde::{Deserialize, Serialize};
use smallvec::SmallVec;

use crate::physics::dynamics::body::BodyId;

/// Identifies which pair of features (vertex, edge, face) produced a contact, so that a solver
/// can match contacts of consecutive steps and reuse their impulses (warm starting).
/// The numbers are only meaningful for the same pair of shapes; equal ids mean "same contact".
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize,
)]
pub struct FeatureId {
    /// A's feature: a face, vertex or edge index, its kind (and its part, in a compound)
    /// tagged in the high bits; 0 but for a part's tag where the contact names no feature
    /// of A, as between closest points.
    pub on_a: u32,
    /// B's feature, numbered as `on_a`.
    pub on_b: u32,
}

/// What kind of feature pair touches, in the report's vocabulary (section 3.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ContactKind {
    /// A vertex of one body against a face of the other; the normal is the face normal.
    VertexFace,
    /// Two edges crossing; the normal is along the cross product of the edges.
    EdgeEdge,
    /// At least one curved surface (sphere, capsule, cylinder), or a GJK/EPA witness pair.
    Closest,
}

/// One contact point between two bodies, in world coordinates (conventions in the module
/// comment).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// World position, midway between the two surfaces.
    pub position: DVec3,
    /// Unit normal from A to B.
    pub normal: DVec3,
    /// Signed distance along the normal; negative means penetration.
    pub separation: f64,
    /// Which kind of feature pair touches here.
    pub kind: ContactKind,
    /// Which features touch, so that this contact is found again next step.
    pub feature: FeatureId,
    /// Time of impact within the step (s from the start of the step); 0 for contacts found
    /// at the current configuration.
    pub time_of_impact: f64,
    /// Where the solver applies this contact's impulses: the lever arms from A's and B's
    /// centres of mass, world axes, in the solver's f32. None for a contact generated in
    /// this step, whose impulses act at `position`; a contact carried over from an earlier
    /// step (`manifold_memory`) keeps the arms it was generated with.
    pub levers: Option<[Vec3; 2]>,
}

impl Contact {
    /// Where the solver applies this contact's impulses, from the centres of mass of A and B
    /// at `center_a` and `center_b`: the arms it keeps (`levers`), or those to `position`.
    pub fn lever_arms(&self, center_a: DVec3, center_b: DVec3) -> [DVec3; 2] {
        match self.levers {
            Some(kept) => kept.map(|lever| lever.as_dvec3()),
            None => [self.position - center_a, self.position - center_b],
        }
    }

    /// The contact point on the surface of A.
    pub fn point_on_a(&self) -> DVec3 {
        self.position - self.normal * (0.5 * self.separation)
    }

    /// The contact point on the surface of B.
    pub fn point_on_b(&self) -> DVec3 {
        self.position + self.normal * (0.5 * self.separation)
    }
}

/// All contacts between one pair of bodies, sharing one normal (from A to B).
#[derive(Clone, Debug, PartialEq)]
pub struct ContactManifold {
    /// Body A: the normals point away from it. Its slot, at generation 0 (see `BodyId`):
    /// compare it with a body's id by `BodyId::index`, or look it up with `World::id_at`.
    pub body_a: BodyId,
    /// Body B: the normals point towards it; a slot as `body_a` is.
    pub body_b: BodyId,
    /// Unit, from A to B, world: the deepest contact's normal.
    pub normal: DVec3,
    /// At most `MAX_MANIFOLD_POINTS`, deepest first.
    pub contacts: ManifoldPoints,
}

/// Four well-spread points hold a box face still; more add cost without stability.
pub const MAX_MANIFOLD_POINTS: usize = 4;

/// A manifold's contacts, held inline: every pair's manifold is built anew or carried over
/// at every step, and allocating and freeing a list for each one cost more than moving the
/// larger inline manifolds does (BENCHMARKS.md, "Inline manifold points").
pub type ManifoldPoints = SmallVec<[Contact; MAX_MANIFOLD_POINTS]>;

impl ContactManifold {
    /// Pushes onto `manifolds` the manifold of the contacts that `fill` adds, which it
    /// leaves deepest first: the manifold's normal is the deepest contact's. Returns false,
    /// and pushes nothing, when it adds none. The manifold is built where it is pushed: it
    /// holds its contacts inline, and returning one copied it several times.
    pub fn push_built(
        manifolds: &mut Vec<ContactManifold>,
        body_a: BodyId,
        body_b: BodyId,
        fill: impl FnOnce(&mut ManifoldPoints),
    ) -> bool {
        manifolds.push(ContactManifold {
            body_a,
            body_b,
            normal: DVec3::ZERO,
            contacts: ManifoldPoints::new(),
        });
        let manifold = manifolds.last_mut().expect("just pushed");
        fill(&mut manifold.contacts);
        let Some(deepest) = manifold.contacts.first() else {
            manifolds.pop();
            return false;
        };
        manifold.normal = deepest.normal;
        true
    }

    /// Stamps every contact with the time within the step at which it was found (after a
    /// rewind or a conservative advancement).
    pub fn with_time_of_impact(mut self, time: f64) -> Self {
        for contact in &mut self.contacts {
            contact.time_of_impact = time;
        }
        self
    }

    /// The most negative separation (the deepest penetration), or +∞ when empty.
    pub fn min_separation(&self) -> f64 {
        self.contacts
            .iter()
            .map(|c| c.separation)
            .fold(f64::INFINITY, f64::min)
    }
}
