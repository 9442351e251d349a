//! A min-heap of items named by small integer slots, whose keys can be changed in place.
//!
//! The simplifier keeps one entry per edge (slot: the edge's entity index) and re-keys an edge
//! when a neighbouring collapse changes its cost, instead of pushing a second entry and
//! skipping the stale one later: the heap never holds more entries than there are edges, and
//! no pop is wasted on stale ones. Four children per node: half the depth of a binary heap,
//! and the children of a node share a cache line.
//!
//! Keys are ordered as tuples: equal keys never occur for distinct slots when the key includes
//! the slot's identity, which makes the pop order deterministic.

const NONE: u32 = u32::MAX;
const ARITY: usize = 4;

/// A min-heap of `(key, slot)` with at most one entry per slot.
#[derive(Clone, Debug, Default)]
pub struct IndexedHeap<K> {
    entries: Vec<(K, u32)>,
    /// Each slot's position in `entries`, or `NONE`.
    position: Vec<u32>,
}

impl<K: Ord + Copy> IndexedHeap<K> {
    /// An empty heap for slots `0..slots`.
    pub fn with_slots(slots: usize) -> Self {
        Self {
            entries: Vec::new(),
            position: vec![NONE; slots],
        }
    }

    /// Builds the heap from entries with distinct slots, each below `slots`, in O(n).
    ///
    /// # Panics
    /// If a slot is out of range or repeated.
    pub fn from_entries(slots: usize, entries: Vec<(K, u32)>) -> Self {
        let mut heap = Self {
            entries,
            position: vec![NONE; slots],
        };
        for (i, &(_, slot)) in heap.entries.iter().enumerate() {
            assert_eq!(heap.position[slot as usize], NONE, "slot {slot} repeated");
            heap.position[slot as usize] = i as u32;
        }
        for i in (0..heap.entries.len()).rev() {
            heap.sift_down(i);
        }
        heap
    }

    /// Number of entries.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether the heap is empty.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Sets `slot`'s key, inserting it if absent.
    pub fn set(&mut self, slot: u32, key: K) {
        let at = self.position[slot as usize];
        if at == NONE {
            self.entries.push((key, slot));
            let i = self.entries.len() - 1;
            self.position[slot as usize] = i as u32;
            self.sift_up(i);
        } else {
            let i = at as usize;
            let old = self.entries[i].0;
            self.entries[i].0 = key;
            if key < old {
                self.sift_up(i);
            } else {
                self.sift_down(i);
            }
        }
    }

    /// Removes `slot` if present.
    pub fn remove(&mut self, slot: u32) {
        let at = self.position[slot as usize];
        if at == NONE {
            return;
        }
        let i = at as usize;
        self.position[slot as usize] = NONE;
        let last = self.entries.pop().expect("a present slot has an entry");
        if i < self.entries.len() {
            let old = self.entries[i].0;
            self.entries[i] = last;
            self.position[last.1 as usize] = i as u32;
            if last.0 < old {
                self.sift_up(i);
            } else {
                self.sift_down(i);
            }
        }
    }

    /// Removes and returns the entry with the smallest key.
    pub fn pop(&mut self) -> Option<(K, u32)> {
        let top = *self.entries.first()?;
        self.remove(top.1);
        Some(top)
    }

    fn place(&mut self, i: usize, entry: (K, u32)) {
        self.entries[i] = entry;
        self.position[entry.1 as usize] = i as u32;
    }

    fn sift_up(&mut self, mut i: usize) {
        let entry = self.entries[i];
        while i > 0 {
            let parent = (i - 1) / ARITY;
            if self.entries[parent].0 <= entry.0 {
                break;
            }
            self.place(i, self.entries[parent]);
            i = parent;
        }
        self.place(i, entry);
    }

    fn sift_down(&mut self, mut i: usize) {
        let entry = self.entries[i];
        let n = self.entries.len();
        loop {
            let first = ARITY * i + 1;
            if first >= n {
                break;
            }
            let last = (first + ARITY).min(n);
            let mut best = first;
            for c in first + 1..last {
                if self.entries[c].0 < self.entries[best].0 {
                    best = c;
                }
            }
            if self.entries[best].0 >= entry.0 {
                break;
            }
            self.place(i, self.entries[best]);
            i = best;
        }
        self.place(i, entry);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator, so the test needs no crate.
    fn numbers(seed: u64) -> impl Iterator<Item = u64> {
        let mut x = seed;
        std::iter::from_fn(move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            Some(x)
        })
    }

    #[test]
    fn pops_in_key_order_after_any_mix_of_sets_and_removes() {
        let slots = 300;
        let mut heap: IndexedHeap<(u64, u32)> = IndexedHeap::with_slots(slots);
        let mut model: Vec<Option<u64>> = vec![None; slots];
        let mut rng = numbers(0x9e37_79b9_7f4a_7c15);
        for _ in 0..20_000 {
            let slot = (rng.next().unwrap() % slots as u64) as u32;
            match rng.next().unwrap() % 5 {
                0 => {
                    heap.remove(slot);
                    model[slot as usize] = None;
                }
                1 => {
                    let expected = model
                        .iter()
                        .enumerate()
                        .filter_map(|(s, k)| k.map(|k| (k, s as u32)))
                        .min();
                    assert_eq!(heap.pop().map(|(k, s)| (k.0, s)), expected);
                    if let Some((_, s)) = expected {
                        model[s as usize] = None;
                    }
                }
                _ => {
                    let key = rng.next().unwrap() % 1000;
                    heap.set(slot, (key, slot));
                    model[slot as usize] = Some(key);
                }
            }
            assert_eq!(heap.len(), model.iter().flatten().count());
        }
    }

    #[test]
    fn built_in_bulk_it_pops_sorted() {
        let keys: Vec<u64> = numbers(7).take(1000).map(|x| x % 97).collect();
        let entries = keys
            .iter()
            .enumerate()
            .map(|(s, &k)| ((k, s as u32), s as u32))
            .collect();
        let mut heap = IndexedHeap::from_entries(keys.len(), entries);
        let mut expected: Vec<(u64, u32)> = keys
            .iter()
            .enumerate()
            .map(|(s, &k)| (k, s as u32))
            .collect();
        expected.sort();
        let popped: Vec<(u64, u32)> = std::iter::from_fn(|| heap.pop().map(|(k, _)| k)).collect();
        assert_eq!(popped, expected);
        assert!(heap.is_empty());
    }
}
