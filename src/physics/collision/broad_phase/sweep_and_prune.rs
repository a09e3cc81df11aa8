//! Sweep and prune along one axis: boxes sorted by their minimum on the axis, then each box
//! is tested only against the boxes whose intervals on that axis start before it ends.
//!
//! The axis is the one along which the box centres spread the most, chosen again at every
//! call: a column of bodies must be swept along its height, a floor of them along its width,
//! or the sweep degenerates into all n² tests. The order is kept between calls and re-sorted
//! with a run-adaptive stable sort, which costs O(n) when bodies moved little.

use crate::physics::collision::broad_phase::{BodyPair, BroadPhase, Proxy, sort_pairs};

/// Sweep and prune along the axis of widest spread, with the sort order kept between calls
/// (see the module comment); the default starts with no order.
#[derive(Clone, Debug, Default)]
pub struct SweepAndPrune {
    /// Body indices sorted by `aabb.min[axis]` as of the last call.
    order: Vec<u32>,
    /// The boxes in that order, as the sweep reads them (reused between calls).
    intervals: Vec<Interval>,
    /// The pairs in sweep order, before they are sorted (reused between calls).
    swept: Vec<BodyPair>,
    /// Where each first body's pairs start in the sorted list (reused between calls).
    starts: Vec<usize>,
}

/// One box as the sweep reads it, stored in sweep order: a box's candidates are its next
/// neighbours in memory rather than proxies scattered by body index, and the test of each
/// is the plain comparisons of `Aabb::overlaps`.
#[derive(Clone, Copy, Debug)]
struct Interval {
    /// The box on the sweep axis.
    start: f64,
    end: f64,
    /// Its minimum and maximum on the two other axes.
    across: [[f64; 2]; 2],
    body: u32,
    active: bool,
}

impl Interval {
    /// A box that meets nothing: after every box in the sweep, and ending before them all.
    const EMPTY: Interval = Interval {
        start: f64::INFINITY,
        end: f64::NEG_INFINITY,
        across: [[f64::INFINITY, f64::NEG_INFINITY]; 2],
        body: 0,
        active: false,
    };

    /// A box with a NaN bound (which fails every comparison of `Aabb::overlaps`, so it pairs
    /// with nothing) is swept as `EMPTY`, so that `wants_pair` need not test for it.
    fn of(proxy: &Proxy, body: u32, axis: usize) -> Interval {
        let (min, max) = (proxy.aabb.min, proxy.aabb.max);
        if min.is_nan() || max.is_nan() {
            return Interval {
                body,
                ..Interval::EMPTY
            };
        }
        let [u, v] = [(axis + 1) % 3, (axis + 2) % 3];
        Interval {
            start: min[axis],
            end: max[axis],
            across: [[min[u], max[u]], [min[v], max[v]]],
            body,
            active: proxy.active,
        }
    }

    /// `wants_pair` for a `later` box in the sweep: it starts no earlier than this one (the
    /// order) and no later than this one ends (the sweep's break), so on the sweep axis they
    /// overlap already. All the comparisons are made and combined without branching: which
    /// of them rejects a candidate is unpredictable, and one branch on the result (nearly
    /// always false) is cheaper than mispredicting four.
    #[inline(always)]
    fn wants_pair(&self, later: &Interval) -> bool {
        let crosses = |k: usize| {
            (self.across[k][0] <= later.across[k][1]) & (later.across[k][0] <= self.across[k][1])
        };
        crosses(0) & crosses(1) & (self.active | later.active)
    }
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
    fn fill_pairs_within(
        &mut self,
        proxies: &[Proxy],
        pairs: &mut Vec<BodyPair>,
        limit: usize,
    ) -> bool {
        self.track_body_count(proxies.len());
        let axis = widest_axis(proxies);
        // Where `Interval::of` puts each box: a box with a NaN bound goes last, as `EMPTY`.
        let start = |i: u32| {
            let aabb = &proxies[i as usize].aabb;
            let nan = aabb.min.is_nan() || aabb.max.is_nan();
            if nan { f64::INFINITY } else { aabb.min[axis] }
        };
        self.order.sort_by(|&i, &j| start(i).total_cmp(&start(j)));
        self.intervals.clear();
        (self.intervals)
            .extend((self.order.iter()).map(|&i| Interval::of(&proxies[i as usize], i, axis)));
        self.swept.clear();
        let mut truncated = false;
        'sweep: for (k, p) in self.intervals.iter().enumerate() {
            for q in &self.intervals[k + 1..] {
                if q.start > p.end {
                    break;
                }
                if p.wants_pair(q) {
                    if self.swept.len() >= limit {
                        truncated = true;
                        break 'sweep;
                    }
                    self.swept
                        .push(BodyPair::new(p.body as usize, q.body as usize));
                }
            }
        }
        sorted_by_first_body(&self.swept, proxies.len(), &mut self.starts, pairs);
        truncated
    }
}

/// Replaces the contents of `sorted` with `pairs` in `sort_pairs` order: a counting sort on
/// the first body, then each first body's few pairs sorted on the second. The pairs are
/// distinct, so this is the one sorted order; it replaces a comparison sort of all the
/// pairs, which showed in a rain's profile (BENCHMARKS.md, "Sorting the swept pairs").
fn sorted_by_first_body(
    pairs: &[BodyPair],
    body_count: usize,
    starts: &mut Vec<usize>,
    sorted: &mut Vec<BodyPair>,
) {
    starts.clear();
    starts.resize(body_count + 1, 0);
    for pair in pairs {
        starts[pair.a.index() + 1] += 1;
    }
    for k in 0..body_count {
        starts[k + 1] += starts[k];
    }
    // Every place is written below.
    sorted.clear();
    sorted.extend_from_slice(pairs);
    for pair in pairs {
        let next = &mut starts[pair.a.index()];
        sorted[*next] = *pair;
        *next += 1;
    }
    // Each first body's run now ends where the next one's starts.
    let mut run_start = 0;
    for &run_end in &starts[..body_count] {
        sort_pairs(&mut sorted[run_start..run_end]);
        run_start = run_end;
    }
}
