//! Every pair tested: the report's Algorithm 2 in a double loop. O(n²), the reference.

use crate::physics::collision::broad_phase::{BodyPair, BroadPhase, Proxy, wants_pair};

/// Tests every pair of proxies: O(n²), and the reference the other broad phases are
/// checked against.
#[derive(Clone, Copy, Debug, Default)]
pub struct BruteForce;

impl BroadPhase for BruteForce {
    fn fill_pairs_within(
        &mut self,
        proxies: &[Proxy],
        pairs: &mut Vec<BodyPair>,
        limit: usize,
    ) -> bool {
        pairs.clear();
        for (i, p) in proxies.iter().enumerate() {
            for (j, q) in proxies.iter().enumerate().skip(i + 1) {
                if wants_pair(p, q) {
                    if pairs.len() >= limit {
                        return true;
                    }
                    pairs.push(BodyPair::new(i, j));
                }
            }
        }
        false
    }
}
