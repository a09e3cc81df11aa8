//! The report's spatial partitioning: space cut into cubic cells, each box registered in the
//! cells it covers, and only boxes sharing a cell tested. Rebuilt every call.

use std::collections::HashMap;

use glam::DVec3;

use crate::physics::collision::broad_phase::{BodyPair, BroadPhase, Proxy, sort_pairs, wants_pair};
use crate::physics::geometry::aabb::Aabb;

/// A box covering more cells than this (a ground slab) is kept aside and tested against
/// every other box instead of being written into thousands of cells.
const MAX_CELLS_PER_PROXY: i64 = 64;

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

    /// Whether a box is kept aside rather than written into its cells.
    fn is_oversized(&self, aabb: &Aabb) -> bool {
        let (lo, hi) = self.cell_range(aabb);
        let count = |a: i32, b: i32| i64::from(b) - i64::from(a) + 1;
        count(lo.0, hi.0) * count(lo.1, hi.1) * count(lo.2, hi.2) > MAX_CELLS_PER_PROXY
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
        self.cells.values_mut().for_each(Vec::clear);
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
    fn fill_pairs(&mut self, proxies: &[Proxy], pairs: &mut Vec<BodyPair>) {
        self.rebuild(proxies);
        pairs.clear();
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
        sort_pairs(pairs);
        pairs.dedup();
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
}
