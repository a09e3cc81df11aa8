//! Warm starting: the impulses each contact ended the last step with, found again this step
//! by (body pair, feature pair), so that the solver starts from last step's answer.

use serde::{Deserialize, Serialize};

use crate::physics::collision::contact::{ContactManifold, FeatureId};
use crate::physics::collision::sorted_seek;
use crate::physics::dynamics::body::BodyId;
use crate::physics::solver::soft::{ContactInput, WarmImpulse};

type Key = (BodyId, BodyId, FeatureId);

/// Sorted by body pair, so that a pair's entries are found by a search; within a pair, in
/// the order of its manifold's points. Iteration order is deterministic.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ContactCache {
    entries: Vec<(Key, WarmImpulse)>,
}

impl ContactCache {
    /// The solver's view of this step's contacts, warm-started from the cache, into `inputs`
    /// (emptied first; kept by the caller so that its room is reused).
    pub fn solver_inputs(&self, manifolds: &[ContactManifold], inputs: &mut Vec<ContactInput>) {
        inputs.clear();
        // The manifolds come in pair order, so each pair's entries are found by walking on
        // from the last pair's (see `sorted_seek`); its few points are then looked up
        // among a handful.
        let mut cursor = 0;
        for m in manifolds {
            let pair = (m.body_a, m.body_b);
            let start = sorted_seek::seek(&self.entries, pair_of, &pair, &mut cursor);
            let rest = &self.entries[start..];
            let remembered = &rest[..rest.iter().take_while(|e| pair_of(e) == pair).count()];
            inputs.extend(m.contacts.iter().map(|c| {
                ContactInput {
                    a: m.body_a.index(),
                    b: m.body_b.index(),
                    point: c.position,
                    normal: c.normal,
                    separation: c.separation,
                    warm_impulse: (remembered.iter())
                        .find(|((_, _, feature), _)| *feature == c.feature)
                        .map_or_else(WarmImpulse::default, |entry| entry.1),
                }
            }));
        }
    }

    /// Remembers the impulses the solver returned, in the order of `solver_inputs`.
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
        // The manifolds come in pair order, and so do the entries. Within a pair they stay in
        // their manifold's order: `solver_inputs` looks a point up among its pair's few
        // entries, and finds the first with its feature (a feature pair found twice keeps
        // the first impulse). A caller that hands the manifolds in another order gets them
        // sorted by pair, stably.
        if !self.entries.is_sorted_by_key(pair_of) {
            self.entries.sort_by_key(pair_of);
        }
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
    }

    /// Drops the impulses of body slot `index` (a new body took it).
    pub fn forget_body(&mut self, index: usize) {
        let other = |((a, b, _), _): &(Key, WarmImpulse)| a.index() != index && b.index() != index;
        self.entries.retain(other);
    }
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
            })
            .collect();
        ContactManifold {
            body_a: BodyId(a),
            body_b: BodyId(b),
            normal: DVec3::Y,
            contacts,
        }
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
            cache.solver_inputs(&manifolds, &mut inputs);
            let found: Vec<f64> = inputs.iter().map(|i| i.warm_impulse.normal).collect();
            let expected: Vec<f64> = (0..count).map(|k| impulse(k).normal).collect();
            assert_eq!(found, expected);
        }
    }
}
