//! Graph colouring of the contacts, so that the soft solver can work on many at once.
//!
//! The points of one manifold (a run of contacts with the same two bodies) form a unit
//! that one thread solves in order. Units get colours greedily, in contact order: the
//! lowest colour that neither of their moving bodies has yet. Within a colour no two units
//! share a moving body, so they can be solved in any order or all at once with the same
//! result to the last bit; colours are solved one after the other. Bodies that do not move
//! in the step (static, asleep) never conflict: nothing writes to them.
//!
//! The colouring depends only on the contacts, never on the number of threads, so neither
//! do the results.
//!
//! Colour order is not contact order, and one pass of sequential impulses converges better
//! in contact order on stacks (bodies are added bottom up, so pairs run bottom up): an awake
//! pyramid shakes markedly more in colour order (BENCHMARKS.md, "Colour order on stacks").
//! So only steps with at least `MIN_COLORED_CONTACTS` contacts are
//! coloured, where the threads pay most; smaller ones are solved serially with the result
//! of contact order.
//!
//! Serially, contact order itself is a chain: the points of a manifold, and the manifolds
//! up a stack, each wait for the impulse before them on a shared body, and the processor
//! cannot start one before the last is stored. So the contacts are put in waves instead:
//! a contact's wave is one past the latest wave of the contacts before it on either of its
//! moving bodies. Contacts on a shared moving body keep their contact order, and the others
//! touch disjoint bodies, so wave order gives contact order's result to the last bit, while
//! neighbours in it are independent and overlap in the processor.

use std::ops::Range;

/// Colours a step may use; units that find none free go to the last, solved serially.
pub const MAX_COLORS: usize = 64;
/// Below this many contacts a step is not coloured (see the module comment).
pub const MIN_COLORED_CONTACTS: usize = 4096;
const SERIAL_COLOR: usize = MAX_COLORS - 1;

/// The contacts in colour order, kept between steps so that no step allocates.
#[derive(Clone, Debug, Default)]
pub struct ContactColors {
    /// Contact indices, colour by colour (or wave by wave); within one, in contact order.
    pub order: Vec<u32>,
    /// Where colour (or wave) k's contacts are in `order`: `starts[k]..starts[k + 1]`.
    starts: Vec<usize>,
    /// The next free place of each colour while sorting.
    next: Vec<usize>,
    /// The colours in use: their contacts in `order`, and whether they may run at once.
    used_ranges: Vec<(Range<usize>, bool)>,
    /// The colours each moving body already has, one bit per colour, by slot.
    used: Vec<u64>,
    /// The colour or, when not coloured, the wave of each contact: what it is sorted by.
    key_of: Vec<u32>,
    /// The latest wave of each moving body's contacts so far, by slot.
    last_wave: Vec<u32>,
    /// Where each contact ended up in `order`.
    pub position_of: Vec<u32>,
}

impl ContactColors {
    /// Colours the contacts, given the two slots of each (`fixed_slot` for a body that does
    /// not move) and the number of slots.
    pub fn assign(
        &mut self,
        slots: impl ExactSizeIterator<Item = [u32; 2]>,
        slot_count: usize,
        fixed_slot: u32,
    ) {
        self.key_of.clear();
        if slots.len() >= MIN_COLORED_CONTACTS {
            self.color(slots, slot_count, fixed_slot);
            self.sort_by_key(MAX_COLORS);
            self.collect_color_ranges();
        } else {
            let waves = self.put_in_waves(slots, slot_count, fixed_slot);
            self.sort_by_key(waves);
            self.used_ranges.clear();
            self.used_ranges.push((0..self.order.len(), false));
        }
    }

    fn color(&mut self, slots: impl Iterator<Item = [u32; 2]>, slot_count: usize, fixed_slot: u32) {
        self.used.clear();
        self.used.resize(slot_count, 0);
        let mut unit: Option<([u32; 2], usize)> = None;
        for pair in slots {
            let color = match unit {
                Some((current, color)) if current == pair => color,
                _ => self.first_free(pair, fixed_slot),
            };
            unit = Some((pair, color));
            self.key_of.push(color as u32);
        }
    }

    /// Gives each contact its wave (see the module comment); returns the number of waves.
    fn put_in_waves(
        &mut self,
        slots: impl Iterator<Item = [u32; 2]>,
        slot_count: usize,
        fixed_slot: u32,
    ) -> usize {
        self.last_wave.clear();
        self.last_wave.resize(slot_count, 0);
        // The fixed slot is never written, so it orders nothing: its wave stays 0.
        let mut waves = 0;
        for [a, b] in slots {
            let wave = self.last_wave[a as usize].max(self.last_wave[b as usize]) + 1;
            for slot in [a, b] {
                if slot != fixed_slot {
                    self.last_wave[slot as usize] = wave;
                }
            }
            self.key_of.push(wave - 1);
            waves = waves.max(wave as usize);
        }
        waves
    }

    /// The lowest colour neither moving body has, taken for both.
    fn first_free(&mut self, pair: [u32; 2], fixed_slot: u32) -> usize {
        let moving = pair.iter().filter(|&&slot| slot != fixed_slot);
        let taken = moving
            .clone()
            .fold(0, |mask, &slot| mask | self.used[slot as usize]);
        let color = ((!taken).trailing_zeros() as usize).min(SERIAL_COLOR);
        for &slot in moving {
            self.used[slot as usize] |= 1 << color;
        }
        color
    }

    /// A counting sort of the contacts by key (below `key_count`), stable within a key.
    fn sort_by_key(&mut self, key_count: usize) {
        self.starts.clear();
        self.starts.resize(key_count + 1, 0);
        for &key in &self.key_of {
            self.starts[key as usize + 1] += 1;
        }
        for k in 0..key_count {
            self.starts[k + 1] += self.starts[k];
        }
        self.next.clear();
        self.next.extend_from_slice(&self.starts);
        self.order.clear();
        self.order.resize(self.key_of.len(), 0);
        self.position_of.clear();
        self.position_of.resize(self.key_of.len(), 0);
        for (contact, &key) in self.key_of.iter().enumerate() {
            let position = self.next[key as usize];
            self.next[key as usize] += 1;
            self.order[position] = contact as u32;
            self.position_of[contact] = position as u32;
        }
    }

    /// The ranges of the colour-ordered contacts, one per colour in use, and whether the
    /// contacts in it may be solved at the same time (all but the serial colour).
    pub fn ranges(&self) -> impl Iterator<Item = (Range<usize>, bool)> + '_ {
        self.used_ranges.iter().cloned()
    }

    fn collect_color_ranges(&mut self) {
        self.used_ranges.clear();
        for k in 0..MAX_COLORS {
            let range = self.starts[k]..self.starts[k + 1];
            if !range.is_empty() {
                self.used_ranges.push((range, k != SERIAL_COLOR));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FIXED: u32 = 0;

    fn colored(pairs: &[[u32; 2]], slots: usize) -> ContactColors {
        let mut colors = ContactColors::default();
        colors.assign(pairs.iter().copied(), slots, FIXED);
        colors
    }

    /// Copies of a scene on their own bodies (slot 0 stays the shared ground), until there
    /// are enough contacts to be coloured at all.
    fn copies(pairs: &[[u32; 2]], bodies: u32) -> (Vec<[u32; 2]>, usize) {
        let count = MIN_COLORED_CONTACTS.div_ceil(pairs.len()) as u32;
        let shift = |slot: u32, k: u32| {
            if slot == FIXED {
                FIXED
            } else {
                slot + k * bodies
            }
        };
        let all = (0..count)
            .flat_map(|k| pairs.iter().map(move |p| p.map(|slot| shift(slot, k))))
            .collect();
        (all, (count * bodies + 1) as usize)
    }

    /// Too few contacts: one serial range; a chain through moving bodies keeps its order.
    #[test]
    fn few_contacts_keep_contact_order() {
        let pairs = [[0, 1], [1, 2], [2, 3]];
        let colors = colored(&pairs, 4);
        let ranges: Vec<_> = colors.ranges().collect();
        assert_eq!(ranges, vec![(0..3, false)]);
        assert_eq!(colors.order, vec![0, 1, 2]);
    }

    /// Two manifolds on the ground, on different bodies: their points alternate, each
    /// manifold's in its own order.
    #[test]
    fn independent_manifolds_interleave() {
        let pairs = [[0, 1], [0, 1], [0, 1], [1, 2], [0, 3], [0, 3]];
        let colors = colored(&pairs, 4);
        // Waves: 1 2 3 4 for body 1 (then 2 on it), 1 2 for body 3.
        assert_eq!(colors.order, vec![0, 4, 1, 5, 2, 3]);
        for (contact, &position) in colors.position_of.iter().enumerate() {
            assert_eq!(colors.order[position as usize], contact as u32);
        }
    }

    /// In wave order, every two contacts that share a moving body keep their contact order:
    /// what makes the serial result that of contact order.
    #[test]
    fn waves_keep_the_order_of_contacts_on_a_shared_body() {
        // A deterministic jumble of pairs over 12 slots, slot 0 the fixed one.
        let mut state = 12345u32;
        let mut next = || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 16) % 12
        };
        let pairs: Vec<[u32; 2]> = (0..500).map(|_| [next(), next()]).collect();
        let colors = colored(&pairs, 12);
        assert_eq!(colors.ranges().collect::<Vec<_>>(), vec![(0..500, false)]);
        let mut sorted = colors.order.clone();
        sorted.sort();
        assert_eq!(sorted, (0..500).collect::<Vec<u32>>());
        for i in 0..pairs.len() {
            for j in i + 1..pairs.len() {
                let shared = pairs[i]
                    .iter()
                    .any(|&s| s != FIXED && pairs[j].contains(&s));
                if shared {
                    assert!(colors.position_of[i] < colors.position_of[j], "{i} and {j}");
                }
            }
        }
    }

    /// No two units of a colour share a moving body, the points of one manifold stay
    /// together and in order, and every contact appears once.
    #[test]
    fn a_color_never_shares_a_moving_body() {
        // A chain 1-2-3-4 on the ground (slot 0), with two-point manifolds.
        let pairs = [
            [0, 1],
            [0, 1],
            [1, 2],
            [1, 2],
            [2, 3],
            [0, 2],
            [3, 4],
            [3, 4],
            [0, 4],
        ];
        let (pairs, slots) = copies(&pairs, 4);
        let colors = colored(&pairs, slots);
        let mut seen = vec![false; pairs.len()];
        for (range, parallel) in colors.ranges() {
            assert!(parallel);
            let mut bodies = vec![];
            let mut previous: Option<[u32; 2]> = None;
            for &contact in &colors.order[range] {
                let pair = pairs[contact as usize];
                assert!(!seen[contact as usize]);
                seen[contact as usize] = true;
                if previous != Some(pair) {
                    for slot in pair.into_iter().filter(|&s| s != FIXED) {
                        assert!(!bodies.contains(&slot), "slot {slot} twice in a colour");
                        bodies.push(slot);
                    }
                }
                previous = Some(pair);
            }
        }
        assert!(seen.iter().all(|&s| s));
        // The two points of the first manifold are next to each other, in order.
        let first = colors.position_of[0] as usize;
        assert_eq!(colors.order[first + 1], 1);
        // Greedy on this chain needs three colours: 1-2 and 2-3 meet 0-1's and each other's.
        assert_eq!(colors.ranges().count(), 3);
    }

    /// A body touching more than the colours can hold sends the rest to the serial colour.
    #[test]
    fn overflow_goes_to_the_serial_color() {
        let leaves = MIN_COLORED_CONTACTS as u32;
        let pairs: Vec<[u32; 2]> = (2..2 + leaves).map(|k| [1, k]).collect();
        let colors = colored(&pairs, leaves as usize + 2);
        let ranges: Vec<_> = colors.ranges().collect();
        assert_eq!(ranges.len(), MAX_COLORS);
        let (last, parallel) = ranges.last().unwrap().clone();
        assert!(!parallel);
        assert_eq!(last.len(), pairs.len() - (MAX_COLORS - 1));
    }
}
