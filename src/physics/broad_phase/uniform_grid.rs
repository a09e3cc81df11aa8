//! The report's spatial partitioning: space cut into cubic cells, each box registered in the
//! cells it covers, and only boxes sharing a cell tested. Rebuilt every call.

use std::collections::HashMap;

use glam::DVec3;

use crate::physics::aabb::Aabb;
use crate::physics::broad_phase::{BodyPair, BroadPhase, Proxy, wants_pair};

/// A box covering more cells than this (a ground slab) is kept aside and tested against
/// every other box instead of being written into thousands of cells.
const MAX_CELLS_PER_PROXY: i64 = 64;

type Cell = (i32, i32, i32);

#[derive(Clone, Debug)]
pub struct UniformGrid {
    cell_size: f64,
    cells: HashMap<Cell, Vec<u32>>,
    oversized: Vec<u32>,
}

impl UniformGrid {
    /// `cell_size` in metres; values that are not positive and finite fall back to 1 m.
    pub fn new(cell_size: f64) -> Self {
        let cell_size = if cell_size.is_finite() && cell_size > 0.0 {
            cell_size
        } else {
            1.0
        };
        UniformGrid {
            cell_size,
            cells: HashMap::new(),
            oversized: Vec::new(),
        }
    }

    fn cell_range(&self, aabb: &Aabb) -> (Cell, Cell) {
        let index = |v: DVec3| {
            let c = (v / self.cell_size).floor();
            let clamp = |x: f64| x.clamp(i32::MIN as f64, i32::MAX as f64) as i32;
            (clamp(c.x), clamp(c.y), clamp(c.z))
        };
        (index(aabb.min), index(aabb.max))
    }

    fn rebuild(&mut self, proxies: &[Proxy]) {
        self.cells.values_mut().for_each(Vec::clear);
        self.oversized.clear();
        for (index, proxy) in proxies.iter().enumerate() {
            let (lo, hi) = self.cell_range(&proxy.aabb);
            let count = |a: i32, b: i32| i64::from(b) - i64::from(a) + 1;
            let cells = count(lo.0, hi.0) * count(lo.1, hi.1) * count(lo.2, hi.2);
            if cells > MAX_CELLS_PER_PROXY {
                self.oversized.push(index as u32);
                continue;
            }
            for x in lo.0..=hi.0 {
                for y in lo.1..=hi.1 {
                    for z in lo.2..=hi.2 {
                        self.cells.entry((x, y, z)).or_default().push(index as u32);
                    }
                }
            }
        }
    }
}

impl BroadPhase for UniformGrid {
    fn find_pairs(&mut self, proxies: &[Proxy]) -> Vec<BodyPair> {
        self.rebuild(proxies);
        let mut pairs = Vec::new();
        let mut test = |i: u32, j: u32| {
            if i != j && wants_pair(&proxies[i as usize], &proxies[j as usize]) {
                pairs.push(BodyPair::new(i as usize, j as usize));
            }
        };
        for members in self.cells.values() {
            for (k, &i) in members.iter().enumerate() {
                for &j in &members[k + 1..] {
                    test(i, j);
                }
            }
        }
        for &i in &self.oversized {
            for j in 0..proxies.len() as u32 {
                test(i, j);
            }
        }
        // A pair sharing several cells is found once per cell.
        pairs.sort_unstable();
        pairs.dedup();
        pairs
    }
}
