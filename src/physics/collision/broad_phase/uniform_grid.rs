//! The report's spatial partitioning: space cut into cubic cells, each box registered in the
//! cells it covers, and only boxes sharing a cell tested. Rebuilt every call.

use std::collections::HashMap;

use glam::DVec3;

use crate::physics::collision::broad_phase::{BodyPair, BroadPhase, Proxy, sort_pairs, wants_pair};
use crate::physics::geometry::aabb::Aabb;

/// A box covering more cells than this (a ground slab, a body at 3e8 m/s, any box in a
/// world of tiny cells) is kept aside and tested against every other box instead of being
/// written into thousands of cells. The grid so never holds more than this many cells per
/// box, whatever the cell size or speeds.
pub const MAX_CELLS_PER_PROXY: u64 = 64;

type Cell = (i32, i32, i32);

/// Spatial hashing into cubic cells, rebuilt at every call; a box covering many cells is
/// tested against every other box instead (see the module comment).
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

    /// Whether a box is kept aside rather than written into its cells. Each axis can span
    /// 2³² cells, so the product is taken with checked arithmetic: wrapped, it once read a
    /// box of 2⁹⁶ cells as one of none and the rebuild tried to fill them all.
    fn is_oversized(&self, aabb: &Aabb) -> bool {
        let (lo, hi) = self.cell_range(aabb);
        // Empty when hi < lo (an inverted box), which covers no cell.
        let count = |a: i32, b: i32| u64::try_from(i64::from(b) - i64::from(a) + 1).unwrap_or(0);
        let cells = count(lo.0, hi.0)
            .checked_mul(count(lo.1, hi.1))
            .and_then(|c| c.checked_mul(count(lo.2, hi.2)));
        cells.is_none_or(|c| c > MAX_CELLS_PER_PROXY)
    }

    /// Cells the grid holds after the last call: those written by it or by the call before
    /// (kept for reuse), so at most 2 × `MAX_CELLS_PER_PROXY` per box.
    pub fn cell_count(&self) -> usize {
        self.cells.len()
    }

    /// The cells the given boxes are written into, as boxes, each once and in a fixed order
    /// (for drawing the grid the broad phase works with). Oversized boxes take no cell.
    pub fn occupied_cells<'a>(&self, boxes: impl IntoIterator<Item = &'a Aabb>) -> Vec<Aabb> {
        let mut cells = Vec::new();
        for aabb in boxes {
            if self.is_oversized(aabb) {
                continue;
            }
            let (lo, hi) = self.cell_range(aabb);
            for x in lo.0..=hi.0 {
                for y in lo.1..=hi.1 {
                    for z in lo.2..=hi.2 {
                        cells.push((x, y, z));
                    }
                }
            }
        }
        cells.sort_unstable();
        cells.dedup();
        let size = self.cell_size;
        cells
            .into_iter()
            .map(|(x, y, z)| {
                let min = DVec3::new(x as f64, y as f64, z as f64) * size;
                Aabb {
                    min,
                    max: min + DVec3::splat(size),
                }
            })
            .collect()
    }

    fn rebuild(&mut self, proxies: &[Proxy]) {
        // Cells the last call left empty are dropped rather than kept: a fast body enters
        // new cells every step, and keeping the ones it left grew the map without end.
        self.cells.retain(|_, members| {
            let used = !members.is_empty();
            members.clear();
            used
        });
        self.oversized.clear();
        for (index, proxy) in proxies.iter().enumerate() {
            if self.is_oversized(&proxy.aabb) {
                self.oversized.push(index as u32);
                continue;
            }
            let (lo, hi) = self.cell_range(&proxy.aabb);
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
    fn fill_pairs_within(
        &mut self,
        proxies: &[Proxy],
        pairs: &mut Vec<BodyPair>,
        limit: usize,
    ) -> bool {
        self.rebuild(proxies);
        pairs.clear();
        // False for a new pair once `limit` distinct pairs are held. A pair sharing several
        // cells is found once per cell, so duplicates are dropped before concluding that
        // the list is full; once full it stays sorted, and a pair it holds is no loss.
        let mut full = false;
        let mut keep = |i: u32, j: u32| {
            if i == j || !wants_pair(&proxies[i as usize], &proxies[j as usize]) {
                return true;
            }
            let pair = BodyPair::new(i as usize, j as usize);
            if !full && pairs.len() >= limit {
                sort_pairs(pairs);
                pairs.dedup();
                full = pairs.len() >= limit;
            }
            if full {
                return pairs.binary_search(&pair).is_ok();
            }
            pairs.push(pair);
            true
        };
        let mut truncated = false;
        'cells: for members in self.cells.values() {
            for (k, &i) in members.iter().enumerate() {
                for &j in &members[k + 1..] {
                    if !keep(i, j) {
                        truncated = true;
                        break 'cells;
                    }
                }
            }
        }
        if !truncated {
            'oversized: for &i in &self.oversized {
                for j in 0..proxies.len() as u32 {
                    if !keep(i, j) {
                        truncated = true;
                        break 'oversized;
                    }
                }
            }
        }
        sort_pairs(pairs);
        pairs.dedup();
        truncated
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn aabb(min: [f64; 3], max: [f64; 3]) -> Aabb {
        Aabb {
            min: DVec3::from(min),
            max: DVec3::from(max),
        }
    }

    #[test]
    fn occupied_cells_are_the_cells_a_box_touches_once_each() {
        let grid = UniformGrid::new(0.5);
        // Spans x in [0.2, 0.7] (cells 0 and 1), y and z inside cell 0; the second box
        // lies in cell (1, 0, 0) again.
        let boxes = [
            aabb([0.2, 0.1, 0.1], [0.7, 0.4, 0.4]),
            aabb([0.6, 0.1, 0.1], [0.9, 0.2, 0.2]),
        ];
        let cells = grid.occupied_cells(&boxes);
        assert_eq!(
            cells,
            vec![
                aabb([0.0, 0.0, 0.0], [0.5, 0.5, 0.5]),
                aabb([0.5, 0.0, 0.0], [1.0, 0.5, 0.5])
            ]
        );
        // Negative coordinates floor down: [-0.1, 0.1] covers cells -1 and 0 on each axis.
        assert_eq!(grid.occupied_cells(&[aabb([-0.1; 3], [0.1; 3])]).len(), 8);
        // A ground slab covering thousands of cells is kept aside, as in `find_pairs`.
        let slab = aabb([-50.0, -1.0, -50.0], [50.0, 0.0, 50.0]);
        assert!(grid.occupied_cells(&[slab]).is_empty());
    }

    /// A box spanning every cell index on all three axes (2³² each) covers 2⁹⁶ cells. The
    /// product wrapped to 0 in i64, so such a box was written into every one of its cells.
    #[test]
    fn a_box_spanning_all_cell_indices_is_oversized() {
        let grid = UniformGrid::new(1e-3);
        let huge = aabb([-1e300; 3], [1e300; 3]);
        assert!(grid.is_oversized(&huge));
        assert!(grid.occupied_cells(&[huge]).is_empty());
        // 2³² × 2³² × 1 cells: the product of two axes alone overflows 64 bits.
        let sheet = aabb([-1e300, -1e300, 0.0], [1e300, 1e300, 0.0005]);
        assert!(grid.is_oversized(&sheet));
        // 4 × 4 × 4 = MAX_CELLS_PER_PROXY cells is still written in; one more layer is not.
        assert!(!grid.is_oversized(&aabb([0.0; 3], [0.0039; 3])));
        assert!(grid.is_oversized(&aabb([0.0; 3], [0.0039, 0.0039, 0.0049])));
    }

    /// A body crossing new cells every call leaves no trail of empty cells: the grid holds
    /// only the cells of the last two calls' boxes.
    #[test]
    fn cells_left_behind_are_dropped() {
        let mut grid = UniformGrid::new(1.0);
        let proxy = |x: f64| Proxy {
            aabb: aabb([x, 0.1, 0.1], [x + 0.5, 0.4, 0.4]),
            active: true,
        };
        for step in 0..1000 {
            grid.find_pairs(&[proxy(10.0 * step as f64), proxy(-3.0)]);
            // The still box's cell, and the moving one's cells of this call and the last.
            assert!(grid.cell_count() <= 3, "{} cells", grid.cell_count());
        }
    }

    /// A pile of boxes in one cell stops at the limit, with duplicates counted once.
    #[test]
    fn pairs_stop_at_the_limit() {
        let mut grid = UniformGrid::new(1.0);
        // 100 boxes over the same 8 cells: 4950 pairs, each found in 8 cells.
        let proxies = vec![
            Proxy {
                aabb: aabb([-0.1; 3], [0.1; 3]),
                active: true,
            };
            100
        ];
        let mut pairs = Vec::new();
        assert!(!grid.fill_pairs_within(&proxies, &mut pairs, 4950));
        assert_eq!(pairs.len(), 4950);
        assert!(grid.fill_pairs_within(&proxies, &mut pairs, 1000));
        assert_eq!(pairs.len(), 1000);
        assert!(pairs.windows(2).all(|w| w[0] < w[1]));
    }
}
