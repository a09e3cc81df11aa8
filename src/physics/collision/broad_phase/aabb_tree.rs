//! A bounding-volume hierarchy over boxes that do not move: built once in O(n log n) by
//! median splits along the widest axis, then queried in O(log n + hits). The world keeps its
//! idle (static and sleeping) bodies here and queries it with the awake ones only, so a
//! thousand resting bodies add nothing to a step in which they are not touched.

use smallvec::{SmallVec, smallvec};

use crate::physics::geometry::aabb::Aabb;

/// Leaves hold up to this many boxes: below it, testing them all beats descending.
const LEAF_SIZE: usize = 4;

/// A bounding-volume hierarchy over boxes tagged with body indices, built whole and never
/// updated (see the module comment); the default tree is empty.
#[derive(Clone, Debug, Default)]
pub struct AabbTree {
    nodes: Vec<Node>,
    /// The boxes with their body indices, ordered so that every node owns a contiguous run.
    items: Vec<(Aabb, u32)>,
}

#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Aabb,
    /// A leaf owns items[first..first + count]; an inner node (count 0) has its children at
    /// `first` and `first + 1` in `nodes`.
    first: u32,
    count: u32,
}

impl AabbTree {
    /// The tree of `items`, each a box with its body index.
    pub fn build(items: impl IntoIterator<Item = (Aabb, u32)>) -> AabbTree {
        let mut tree = AabbTree::default();
        tree.rebuild(items);
        tree
    }

    /// The tree of `items` in place of this one, in the memory this one held: the world
    /// rebuilds its idle tree whenever a body falls asleep or wakes.
    pub fn rebuild(&mut self, items: impl IntoIterator<Item = (Aabb, u32)>) {
        self.items.clear();
        self.items.extend(items);
        self.nodes.clear();
        self.nodes.reserve(2 * self.items.len() / LEAF_SIZE + 1);
        if !self.items.is_empty() {
            self.nodes.push(Node {
                bounds: bounds_of(&self.items),
                first: 0,
                count: self.items.len() as u32,
            });
            self.split(0);
        }
    }

    /// How many boxes the tree holds.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// Whether the tree holds no box.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Splits node `index` at the median of its box centres along their widest spread.
    fn split(&mut self, index: usize) {
        let Node { first, count, .. } = self.nodes[index];
        if count as usize <= LEAF_SIZE {
            return;
        }
        let range = first as usize..(first + count) as usize;
        let items = &mut self.items[range.clone()];
        let centre = |item: &(Aabb, u32)| item.0.min + item.0.max;
        let (low, high) = items.iter().fold(
            (glam::DVec3::INFINITY, glam::DVec3::NEG_INFINITY),
            |(low, high), item| (low.min(centre(item)), high.max(centre(item))),
        );
        let spread = high - low;
        let axis = (0..3)
            .max_by(|&i, &j| spread[i].total_cmp(&spread[j]))
            .unwrap_or(0);
        let half = items.len() / 2;
        items.select_nth_unstable_by(half, |x, y| centre(x)[axis].total_cmp(&centre(y)[axis]));
        let children = self.nodes.len() as u32;
        for (start, end) in [
            (range.start, range.start + half),
            (range.start + half, range.end),
        ] {
            self.nodes.push(Node {
                bounds: bounds_of(&self.items[start..end]),
                first: start as u32,
                count: (end - start) as u32,
            });
        }
        self.nodes[index].first = children;
        self.nodes[index].count = 0;
        self.split(children as usize);
        self.split(children as usize + 1);
    }

    /// Calls `hit` with the body index of every box that overlaps `query` (touching counts).
    pub fn query(&self, query: &Aabb, mut hit: impl FnMut(u32)) {
        if self.nodes.is_empty() {
            return;
        }
        // Median splits keep the tree about log2(n / LEAF_SIZE) deep and the stack no deeper
        // than that plus one: inline, as every awake body queries once a step.
        let mut stack: SmallVec<[u32; 64]> = smallvec![0];
        while let Some(index) = stack.pop() {
            let node = &self.nodes[index as usize];
            if !node.bounds.overlaps(query) {
                continue;
            }
            if node.count == 0 {
                stack.push(node.first);
                stack.push(node.first + 1);
                continue;
            }
            let leaf = &self.items[node.first as usize..(node.first + node.count) as usize];
            for (aabb, body) in leaf {
                if aabb.overlaps(query) {
                    hit(*body);
                }
            }
        }
    }
}

fn bounds_of(items: &[(Aabb, u32)]) -> Aabb {
    items
        .iter()
        .map(|item| item.0)
        .reduce(|a, b| a.union(&b))
        .expect("never called on an empty run")
}
