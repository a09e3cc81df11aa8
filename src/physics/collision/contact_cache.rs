//! Warm starting: the impulses each contact ended the last step with, found again this step
//! by (body pair, feature pair), so that the solver starts from last step's answer.
//!
//! A point whose feature pair is new takes the impulse of the remembered point of its pair
//! that lay within `MATCH_DISTANCE` of it in body A's frame, if one did and no other point
//! took it. Clipping two faces whose edges line up (a column of equal boxes) names the
//! same corner by a vertex one step and by an edge crossing the next, as round-off falls:
//! matched by feature alone, those corners started from nothing, and a tall column leaned
//! over (BENCHMARKS.md, "Warm starts found by position").

use glam::DVec3;
use serde::{Deserialize, Serialize};
use smallvec::{SmallVec, smallvec};

use crate::physics::collision::contact::{ContactManifold, FeatureId, MAX_MANIFOLD_POINTS};
use crate::physics::collision::manifold_memory::REUSE_DISTANCE;
use crate::physics::collision::sorted_seek;
use crate::physics::dynamics::body::{BodyId, RigidBody};
use crate::physics::solver::soft::{ContactInput, WarmImpulse};

type Key = (BodyId, BodyId, FeatureId);

/// How close, m, in body A's frame, a new contact point must be to a remembered one of the
/// same pair to take its impulse when their feature pairs differ: a quarter of
/// `REUSE_DISTANCE`. A resting corner moves far less between steps, and a manifold's points
/// lie far farther apart.
pub const MATCH_DISTANCE: f64 = REUSE_DISTANCE / 4.0;

/// Sorted by body pair, so that a pair's entries are found by a search; within a pair, in
/// the order of its manifold's points. Iteration order is deterministic.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ContactCache {
    entries: Vec<(Key, WarmImpulse)>,
    /// Each entry's point in body A's frame (relative to its position) where the step that
    /// stored it began; absent from snapshots written before it was kept (then only feature
    /// pairs match).
    #[serde(default)]
    points: Vec<DVec3>,
    /// This step's points in body A's frame, in the order of `solver_inputs`, for `store`.
    #[serde(skip)]
    pending: Vec<DVec3>,
}

impl ContactCache {
    /// The solver's view of this step's contacts, warm-started from the cache, into `inputs`
    /// (emptied first; kept by the caller so that its room is reused).
    pub fn solver_inputs(
        &mut self,
        bodies: &[RigidBody],
        manifolds: &[ContactManifold],
        inputs: &mut Vec<ContactInput>,
    ) {
        inputs.clear();
        self.pending.clear();
        // The manifolds come in pair order, so each pair's entries are found by walking on
        // from the last pair's (see `sorted_seek`); its few points are then looked up
        // among a handful.
        let mut cursor = 0;
        for m in manifolds {
            let pair = (m.body_a, m.body_b);
            let start = sorted_seek::seek(&self.entries, pair_of, &pair, &mut cursor);
            let count = (self.entries[start..].iter())
                .take_while(|e| pair_of(e) == pair)
                .count();
            let (a, b) = (&bodies[m.body_a.index()], &bodies[m.body_b.index()]);
            let first = self.pending.len();
            (self.pending).extend(m.contacts.iter().map(|c| in_frame_of(a, c.position)));
            let found = self.warm_impulses(start..start + count, m, &self.pending[first..]);
            inputs.extend(
                m.contacts
                    .iter()
                    .zip(found)
                    .map(|(c, warm_impulse)| ContactInput {
                        a: m.body_a.index(),
                        b: m.body_b.index(),
                        levers: c.lever_arms(a.position, b.position),
                        normal: c.normal,
                        separation: c.separation,
                        warm_impulse,
                    }),
            );
        }
    }

    /// The warm start of each of `m`'s points (at `points`, in A's frame) among the
    /// remembered entries `range` of its pair: by feature pair, then by position.
    fn warm_impulses(
        &self,
        range: std::ops::Range<usize>,
        m: &ContactManifold,
        points: &[DVec3],
    ) -> ManifoldImpulses {
        let remembered = &self.entries[range.clone()];
        let mut taken: SmallVec<[bool; MAX_MANIFOLD_POINTS]> = smallvec![false; remembered.len()];
        let mut found: SmallVec<[Option<WarmImpulse>; MAX_MANIFOLD_POINTS]> =
            m.contacts.iter().map(|_| None).collect();
        for (k, c) in m.contacts.iter().enumerate() {
            let same = remembered.iter().position(|((_, _, f), _)| *f == c.feature);
            if let Some(j) = same {
                taken[j] = true;
            }
            found[k] = same.map(|j| remembered[j].1);
        }
        let remembered_points = self.points.get(range).unwrap_or_default();
        for (k, point) in points.iter().enumerate() {
            if found[k].is_some() {
                continue;
            }
            let nearest = (remembered_points.iter().enumerate())
                .filter(|(j, _)| !taken[*j])
                .map(|(j, p)| (j, p.distance_squared(*point)))
                .filter(|(_, d)| *d <= MATCH_DISTANCE * MATCH_DISTANCE)
                .min_by(|x, y| x.1.total_cmp(&y.1));
            if let Some((j, _)) = nearest {
                taken[j] = true;
                found[k] = Some(remembered[j].1);
            }
        }
        found.into_iter().map(Option::unwrap_or_default).collect()
    }

    /// Remembers the impulses the solver returned, in the order of `solver_inputs` (the
    /// manifolds and the bodies' poses it was given).
    pub fn store(
        &mut self,
        manifolds: &[ContactManifold],
        impulses: impl Iterator<Item = WarmImpulse>,
    ) {
        self.entries.clear();
        let keys = manifolds.iter().flat_map(|m| {
            m.contacts
                .iter()
                .map(move |c| (m.body_a, m.body_b, c.feature))
        });
        self.entries.extend(keys.zip(impulses));
        std::mem::swap(&mut self.points, &mut self.pending);
        self.pending.clear();
        if self.points.len() != self.entries.len() {
            // Not from `solver_inputs` of these manifolds: match by feature only.
            self.points.clear();
        }
        // The manifolds come in pair order, and so do the entries. Within a pair they stay in
        // their manifold's order: `solver_inputs` looks a point up among its pair's few
        // entries, and finds the first with its feature (a feature pair found twice keeps
        // the first impulse). A caller that hands the manifolds in another order gets them
        // sorted by pair, stably, with their points.
        if !self.entries.is_sorted_by_key(pair_of) {
            self.sort_by_pair();
        }
    }

    fn sort_by_pair(&mut self) {
        if self.points.is_empty() {
            self.entries.sort_by_key(pair_of);
            return;
        }
        let mut both: Vec<_> = self.entries.drain(..).zip(self.points.drain(..)).collect();
        both.sort_by_key(|(entry, _)| pair_of(entry));
        (self.entries, self.points) = both.into_iter().unzip();
    }

    /// The highest body index any entry refers to.
    pub fn max_body_index(&self) -> Option<usize> {
        self.entries
            .iter()
            .map(|((a, b, _), _)| a.index().max(b.index()))
            .max()
    }

    pub fn clear(&mut self) {
        self.entries.clear();
        self.points.clear();
    }

    /// Drops the impulses of body slot `index` (a new body took it).
    pub fn forget_body(&mut self, index: usize) {
        let keep = |((a, b, _), _): &(Key, WarmImpulse)| a.index() != index && b.index() != index;
        if self.points.len() == self.entries.len() {
            let mut entries = self.entries.iter();
            self.points.retain(|_| entries.next().is_some_and(keep));
        } else {
            self.points.clear();
        }
        self.entries.retain(keep);
    }
}

/// One warm start per point of a manifold.
type ManifoldImpulses = SmallVec<[WarmImpulse; MAX_MANIFOLD_POINTS]>;

/// `point` (world) in the frame of `body`, relative to its position.
fn in_frame_of(body: &RigidBody, point: DVec3) -> DVec3 {
    body.orientation.transpose() * (point - body.position)
}

/// The body pair an entry belongs to.
fn pair_of(((a, b, _), _): &(Key, WarmImpulse)) -> (BodyId, BodyId) {
    (*a, *b)
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::physics::collision::contact::{Contact, ContactKind};
    use crate::physics::dynamics::body::BodyDesc;
    use crate::physics::geometry::shape::Shape;

    fn manifold(a: u32, b: u32, features: &[u32]) -> ContactManifold {
        let contacts = features
            .iter()
            .map(|&f| Contact {
                position: DVec3::ZERO,
                normal: DVec3::Y,
                separation: 0.0,
                kind: ContactKind::VertexFace,
                feature: FeatureId { on_a: f, on_b: 0 },
                time_of_impact: 0.0,
                levers: None,
            })
            .collect();
        ContactManifold {
            body_a: BodyId(a),
            body_b: BodyId(b),
            normal: DVec3::Y,
            contacts,
        }
    }

    /// Six bodies, as many as the manifolds below name.
    fn bodies() -> Vec<RigidBody> {
        (0..6)
            .map(|k| {
                let desc = BodyDesc::dynamic(Shape::sphere(0.5)).at(DVec3::X * k as f64);
                RigidBody::from_desc(&desc).unwrap()
            })
            .collect()
    }

    /// A manifold of bodies 0 and 1 with one point per (feature, position).
    fn placed(points: &[(u32, DVec3)]) -> ContactManifold {
        let mut m = manifold(0, 1, &[]);
        m.contacts = (points.iter())
            .map(|&(f, position)| Contact {
                position,
                feature: FeatureId { on_a: f, on_b: 0 },
                ..manifold(0, 1, &[0]).contacts[0]
            })
            .collect();
        m
    }

    /// A corner whose feature pair is renamed (as clipping aligned faces does) keeps its
    /// impulse when it lies within `MATCH_DISTANCE` of where it was in body A's frame, even
    /// after A has moved and turned; one farther off starts from nothing; and a remembered
    /// point gives its impulse to one new point only, the first that finds it nearest.
    #[test]
    fn a_renamed_corner_keeps_its_impulse_where_it_was_on_body_a() {
        let mut bodies = bodies();
        let corners = [
            DVec3::new(0.5, 0.5, 0.5),
            DVec3::new(-0.5, 0.5, 0.5),
            DVec3::new(-0.5, 0.5, -0.5),
            DVec3::new(0.5, 0.5, -0.5),
        ];
        let before = placed(&[
            (1, corners[0]),
            (2, corners[1]),
            (3, corners[2]),
            (4, corners[3]),
        ]);
        let mut cache = ContactCache::default();
        let mut inputs = Vec::new();
        cache.solver_inputs(&bodies, std::slice::from_ref(&before), &mut inputs);
        let impulse = |normal: f64| WarmImpulse {
            normal,
            tangent: [normal, -normal],
        };
        cache.store(
            std::slice::from_ref(&before),
            [10.0, 20.0, 30.0, 40.0].map(impulse).into_iter(),
        );
        // Body A moves 1 m and turns a quarter about y; the corners go with it.
        let turn = glam::DMat3::from_rotation_y(std::f64::consts::FRAC_PI_2);
        let shift = DVec3::new(0.3, 1.0, -0.2);
        bodies[0].position += shift;
        bodies[0].orientation = turn;
        let carried = |p: DVec3| shift + turn * p;
        let off = |k: usize, by: DVec3| carried(corners[k] + by);
        let after = placed(&[
            (101, off(0, DVec3::ZERO)),
            (2, off(1, DVec3::X * 0.1)),
            (103, off(3, DVec3::X * 0.1e-3)),
            (104, off(3, DVec3::X * 0.2e-3)),
        ]);
        cache.solver_inputs(&bodies, std::slice::from_ref(&after), &mut inputs);
        let found: Vec<WarmImpulse> = inputs.iter().map(|i| i.warm_impulse).collect();
        // The renamed corner 0 by position; corner 1 by its feature though it moved 10 cm;
        // corner 3's impulse to the nearer of its two claimants, none to the other.
        let expected = [
            impulse(10.0),
            impulse(20.0),
            impulse(40.0),
            WarmImpulse::default(),
        ];
        assert_eq!(found, expected);
        // A corner 1 mm from where corner 2 was is a new contact.
        let far = placed(&[(105, off(2, DVec3::Z * 1e-3))]);
        cache.solver_inputs(&bodies, std::slice::from_ref(&far), &mut inputs);
        assert_eq!(inputs[0].warm_impulse, WarmImpulse::default());
    }

    /// Forgetting a body drops its pairs' points with their impulses: the other pairs'
    /// renamed points still find theirs by position.
    #[test]
    fn forgetting_a_body_keeps_the_other_pairs_points_in_step() {
        let bodies = bodies();
        let on = |a: u32, b: u32, f: u32, x: f64| {
            let mut m = manifold(a, b, &[f]);
            m.contacts[0].position = DVec3::new(x, 0.5, 0.0);
            m
        };
        let before = [on(0, 1, 1, 0.1), on(1, 2, 2, 1.2), on(2, 3, 3, 2.3)];
        let mut cache = ContactCache::default();
        let mut inputs = Vec::new();
        cache.solver_inputs(&bodies, &before, &mut inputs);
        let impulse = |normal: f64| WarmImpulse {
            normal,
            tangent: [0.0; 2],
        };
        cache.store(&before, [1.0, 2.0, 3.0].map(impulse).into_iter());
        cache.forget_body(1);
        let after = [on(0, 1, 11, 0.1), on(2, 3, 13, 2.3)];
        cache.solver_inputs(&bodies, &after, &mut inputs);
        let found: Vec<f64> = inputs.iter().map(|i| i.warm_impulse.normal).collect();
        assert_eq!(found, [0.0, 3.0]);
    }

    /// Every stored impulse is found again, whether the manifolds come in pair order (each
    /// one's points unsorted) or not; the last order has a pair out of order and, after it,
    /// one that lies before the pair last walked to.
    #[test]
    fn stored_impulses_are_found_again_in_any_manifold_order() {
        for manifolds in [
            vec![manifold(0, 1, &[7, 3, 5]), manifold(0, 2, &[2, 1])],
            vec![manifold(1, 2, &[4, 9]), manifold(0, 1, &[8, 6, 1])],
            vec![
                manifold(0, 1, &[1]),
                manifold(2, 3, &[2, 4]),
                manifold(0, 2, &[5]),
                manifold(1, 5, &[3]),
                manifold(2, 3, &[6]),
            ],
        ] {
            let count = manifolds.iter().map(|m| m.contacts.len()).sum::<usize>();
            let impulse = |k: usize| WarmImpulse {
                normal: k as f64 + 1.0,
                tangent: [0.0; 2],
            };
            let mut cache = ContactCache::default();
            cache.store(&manifolds, (0..count).map(impulse));
            let mut inputs = Vec::new();
            cache.solver_inputs(&bodies(), &manifolds, &mut inputs);
            let found: Vec<f64> = inputs.iter().map(|i| i.warm_impulse.normal).collect();
            let expected: Vec<f64> = (0..count).map(|k| impulse(k).normal).collect();
            assert_eq!(found, expected);
        }
    }
}
