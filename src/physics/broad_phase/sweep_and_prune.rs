//! Sweep and prune along one axis: boxes sorted by their minimum on the axis, then each box
//! is tested only against the boxes whose intervals on that axis start before it ends.
//!
//! The axis is the one along which the box centres spread the most, chosen again at every
//! call: a column of bodies must be swept along its height, a floor of them along its width,
//! or the sweep degenerates into all n² tests. The order is kept between calls and re-sorted
//! with a run-adaptive stable sort, which costs O(n) when bodies moved little.

use crate::physics::broad_phase::{BodyPair, BroadPhase, Proxy, sort_pairs, wants_pair};

#[derive(Clone, Debug, Default)]
pub struct SweepAndPrune {
    /// Body indices sorted by `aabb.min[axis]` as of the last call.
    order: Vec<u32>,
}

impl SweepAndPrune {
    /// Keeps the previous order for bodies that still exist and appends new ones.
    fn track_body_count(&mut self, count: usize) {
        if self.order.len() != count {
            self.order.retain(|&i| (i as usize) < count);
            let known = self.order.len();
            self.order.extend(known as u32..count as u32);
        }
    }
}

/// 0, 1 or 2: the axis with the largest variance of the box centres.
fn widest_axis(proxies: &[Proxy]) -> usize {
    let n = proxies.len().max(1) as f64;
    let centers = proxies.iter().map(|p| p.aabb.min + p.aabb.max);
    let mean = centers.clone().fold(glam::DVec3::ZERO, |sum, c| sum + c) / n;
    let variance = centers.fold(glam::DVec3::ZERO, |sum, c| sum + (c - mean) * (c - mean));
    (0..3)
        .max_by(|&i, &j| variance[i].total_cmp(&variance[j]))
        .unwrap_or(0)
}

impl BroadPhase for SweepAndPrune {
    fn find_pairs(&mut self, proxies: &[Proxy]) -> Vec<BodyPair> {
        self.track_body_count(proxies.len());
        let axis = widest_axis(proxies);
        let start = |i: u32| proxies[i as usize].aabb.min[axis];
        self.order.sort_by(|&i, &j| start(i).total_cmp(&start(j)));
        let mut pairs = Vec::new();
        for (k, &i) in self.order.iter().enumerate() {
            let p = &proxies[i as usize];
            for &j in &self.order[k + 1..] {
                let q = &proxies[j as usize];
                if q.aabb.min[axis] > p.aabb.max[axis] {
                    break;
                }
                if wants_pair(p, q) {
                    pairs.push(BodyPair::new(i as usize, j as usize));
                }
            }
        }
        sort_pairs(&mut pairs);
        pairs
    }
}
