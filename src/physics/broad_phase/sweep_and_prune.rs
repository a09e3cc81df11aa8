//! Sweep and prune along one axis. The body order by box minimum is kept between calls and
//! repaired by insertion sort, which costs O(n + swaps): nearly linear when bodies move a
//! little each step. The sweep then only tests boxes whose intervals on the axis overlap.

use crate::physics::broad_phase::{BodyPair, BroadPhase, Proxy, wants_pair};

#[derive(Clone, Debug)]
pub struct SweepAndPrune {
    /// 0, 1 or 2: x, y or z. Best along the axis where bodies are most spread out.
    axis: usize,
    /// Body indices sorted by `aabb.min[axis]` as of the last call.
    order: Vec<u32>,
}

impl Default for SweepAndPrune {
    fn default() -> Self {
        SweepAndPrune::along(0)
    }
}

impl SweepAndPrune {
    /// Sweeps along x (0), y (1) or z (2); larger values wrap.
    pub fn along(axis: usize) -> Self {
        SweepAndPrune {
            axis: axis % 3,
            order: Vec::new(),
        }
    }

    /// Keeps the previous order for bodies that still exist and appends new ones.
    fn track_body_count(&mut self, count: usize) {
        if self.order.len() != count {
            self.order.retain(|&i| (i as usize) < count);
            let known = self.order.len();
            self.order.extend(known as u32..count as u32);
        }
    }

    fn insertion_sort(&mut self, proxies: &[Proxy]) {
        let key = |i: u32| proxies[i as usize].aabb.min[self.axis];
        for sorted_end in 1..self.order.len() {
            let mut k = sorted_end;
            while k > 0 && key(self.order[k - 1]) > key(self.order[k]) {
                self.order.swap(k - 1, k);
                k -= 1;
            }
        }
    }
}

impl BroadPhase for SweepAndPrune {
    fn find_pairs(&mut self, proxies: &[Proxy]) -> Vec<BodyPair> {
        self.track_body_count(proxies.len());
        self.insertion_sort(proxies);
        let mut pairs = Vec::new();
        for (k, &i) in self.order.iter().enumerate() {
            let p = &proxies[i as usize];
            for &j in &self.order[k + 1..] {
                let q = &proxies[j as usize];
                if q.aabb.min[self.axis] > p.aabb.max[self.axis] {
                    break;
                }
                if wants_pair(p, q) {
                    pairs.push(BodyPair::new(i as usize, j as usize));
                }
            }
        }
        pairs.sort_unstable();
        pairs
    }
}
