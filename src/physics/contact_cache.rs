//! Warm starting: the impulses each contact ended the last step with, found again this step
//! by (body pair, feature pair), so that the solver starts from last step's answer.

use serde::{Deserialize, Serialize};

use crate::physics::body::BodyId;
use crate::physics::contact::{ContactManifold, FeatureId};
use crate::physics::soft_solver::{ContactInput, WarmImpulse};

type Key = (BodyId, BodyId, FeatureId);

/// Sorted by key, so lookups are binary searches and iteration order is deterministic.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ContactCache {
    entries: Vec<(Key, WarmImpulse)>,
}

impl ContactCache {
    fn lookup(&self, key: &Key) -> WarmImpulse {
        self.entries
            .binary_search_by(|(k, _)| k.cmp(key))
            .map(|index| self.entries[index].1)
            .unwrap_or_default()
    }

    /// The solver's view of this step's contacts, warm-started from the cache, into `inputs`
    /// (emptied first; kept by the caller so that its room is reused).
    pub fn solver_inputs(&self, manifolds: &[ContactManifold], inputs: &mut Vec<ContactInput>) {
        inputs.clear();
        let contacts = manifolds
            .iter()
            .flat_map(|m| m.contacts.iter().map(move |c| (m, c)));
        inputs.extend(contacts.map(|(m, c)| ContactInput {
            a: m.body_a.index(),
            b: m.body_b.index(),
            point: c.position,
            normal: c.normal,
            separation: c.separation,
            warm_impulse: self.lookup(&(m.body_a, m.body_b, c.feature)),
        }));
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
        // Unstable: sorts in place (a stable sort allocates). Equal keys are rare (a feature
        // pair found twice) and which one is kept is the same on every run.
        self.entries.sort_unstable_by_key(|entry| entry.0);
        self.entries.dedup_by(|x, y| x.0 == y.0);
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
}
