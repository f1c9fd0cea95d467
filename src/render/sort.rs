//! The frame's sorts of many items by an f32 key on hosts: a deep tile's spheres (`lanes`) and
//! a light's sweep (`sweep`). A radix sort of the keys' bits: four byte-wide passes over the
//! items, where a sort by comparisons takes about log₂ n passes and fetches two keys for each
//! comparison.

/// Below this many items an insertion sort, which needs no room and costs less than four passes
/// over 256 counts.
const RADIX_FROM: usize = 64;

/// Sorts `items` by `key` in [`f32::total_cmp`]'s order, equal keys in their order: a radix sort
/// of the keys' bits, a byte a pass from the low one, each pass stable, between the items and
/// `room` (whatever it held, overwritten), skipping a byte that every item shares; below
/// [`RADIX_FROM`] items an insertion sort. With less room than items it sorts them by
/// comparisons instead, equal keys then in any order (no caller gives less).
pub(super) fn radix_sort<T: Copy>(items: &mut [T], room: &mut [T], key: impl Fn(&T) -> f32) {
    let n = items.len();
    if n < RADIX_FROM {
        for i in 1..n {
            let mut j = i;
            while j > 0 {
                let (Some(a), Some(b)) = (items.get(j - 1), items.get(j)) else {
                    break;
                };
                if !key(a).total_cmp(&key(b)).is_gt() {
                    break;
                }
                items.swap(j - 1, j);
                j -= 1;
            }
        }
        return;
    }
    // Only the items' length of the room: the rest is not theirs.
    let Some(room) = room.get_mut(..n) else {
        items.sort_unstable_by(|a, b| key(a).total_cmp(&key(b)));
        return;
    };
    // The bits as unsigned integers in `total_cmp`'s order: negatives reversed below the
    // positives.
    let bits = |x: &T| {
        let b = key(x).to_bits();
        if b >> 31 == 1 {
            !b
        } else {
            b | 1 << 31
        }
    };
    // Every pass's counts from one read of the keys.
    let mut counts = [[0usize; 256]; 4];
    for x in &*items {
        let b = bits(x);
        for (pass, at) in counts.iter_mut().enumerate() {
            if let Some(a) = at.get_mut((b >> (8 * pass)) as usize & 0xff) {
                *a += 1;
            }
        }
    }
    // Whether the items are in `room` after the passes so far.
    let mut in_room = false;
    for (pass, at) in counts.iter_mut().enumerate() {
        let byte = |x: &T| (bits(x) >> (8 * pass)) as usize & 0xff;
        // A byte all the items share leaves their order as it is: no pass (the high byte of
        // keys of one sign and magnitude, often).
        if items.first().and_then(|x| at.get(byte(x))) == Some(&n) {
            continue;
        }
        // Where each byte's items go: the counts of the smaller bytes.
        starts(at);
        let (from, to) = if in_room {
            (&*room, &mut *items)
        } else {
            (&*items, &mut *room)
        };
        for x in from {
            if let Some(a) = at.get_mut(byte(x)) {
                if let Some(slot) = to.get_mut(*a) {
                    *slot = *x;
                }
                *a += 1;
            }
        }
        in_room = !in_room;
    }
    if in_room {
        // Both of length n: a copy.
        for (x, y) in items.iter_mut().zip(&*room) {
            *x = *y;
        }
    }
}

/// Counts to the first position of each byte's items: the sum of the counts before it.
#[inline(always)]
fn starts(at: &mut [usize; 256]) {
    let mut sum = 0;
    for a in at.iter_mut() {
        (*a, sum) = (sum, sum + *a);
    }
}
