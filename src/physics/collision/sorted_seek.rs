//! Finding keys in a sorted list when they are asked for in ascending order, as the narrow
//! phase and the warm start ask for body pairs: the next one sought is usually a few entries
//! past the last one found, so walking there from a cursor beats a binary search per key,
//! whose probes each land in another entry's cache lines.

/// Entries a search steps through from its cursor before it bisects the rest.
const WALK: usize = 8;

/// The first index of `items` (sorted by `key`) whose key is not below `sought`, searched
/// from `*cursor`, which is left at that index. A key before the cursor, or far past it, is
/// found by a binary search; the answer is always `partition_point`'s. Inlined: the key
/// function is a field read, and called through a frame it costs more than the walk.
#[inline]
pub fn seek<T, K: Ord>(
    items: &[T],
    key: impl Fn(&T) -> K,
    sought: &K,
    cursor: &mut usize,
) -> usize {
    let mut at = (*cursor).min(items.len());
    if at > 0 && key(&items[at - 1]) >= *sought {
        at = items[..at].partition_point(|item| key(item) < *sought);
    } else {
        let walk_end = (at + WALK).min(items.len());
        while at < walk_end && key(&items[at]) < *sought {
            at += 1;
        }
        if at == walk_end {
            at += items[at..].partition_point(|item| key(item) < *sought);
        }
    }
    *cursor = at;
    at
}

#[cfg(test)]
mod tests {
    use super::*;

    /// In ascending order, in a scrambled order and for keys it does not hold, from one
    /// cursor, the search gives `partition_point`'s answer.
    #[test]
    fn seeking_from_a_cursor_finds_what_partition_point_finds() {
        // Every third number below 300, some twice.
        let items: Vec<u32> = (0..300)
            .filter(|k| k % 3 == 0)
            .flat_map(|k| [k, k / 6 * 6])
            .collect();
        let mut sorted = items.clone();
        sorted.sort();
        let ascending = 0..310u32;
        let scrambled = (0..2000u32).map(|k| (k * 7919) % 310);
        let mut cursor = 0;
        for sought in ascending.chain(scrambled) {
            let found = seek(&sorted, |&k| k, &sought, &mut cursor);
            assert_eq!(found, sorted.partition_point(|&k| k < sought), "{sought}");
            assert_eq!(cursor, found);
        }
    }
}
