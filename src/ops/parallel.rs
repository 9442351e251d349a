//! Work spread over the machine's cores: a slice cut into one contiguous chunk a thread, each
//! item computed from shared inputs alone, so the result is the same bits on any number of
//! cores (what the step-by-step runs rely on to end where the whole run ends).

/// Below this many items a chunk, a thread costs more to start than it saves.
pub(crate) const MIN_ITEMS_PER_THREAD: usize = 4096;

/// Runs `f(index, item)` over `items`, split into contiguous chunks over the available cores
/// (one thread for slices shorter than two chunks of [`MIN_ITEMS_PER_THREAD`]). Each call sees
/// its own item alone, so the order the chunks run in changes nothing.
pub(crate) fn in_parallel<T: Send>(items: &mut [T], f: impl Fn(usize, &mut T) + Sync) {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let threads = cores.min(items.len() / MIN_ITEMS_PER_THREAD).max(1);
    if threads == 1 {
        items.iter_mut().enumerate().for_each(|(i, x)| f(i, x));
        return;
    }
    let chunk = items.len().div_ceil(threads);
    std::thread::scope(|scope| {
        let f = &f;
        for (c, part) in items.chunks_mut(chunk).enumerate() {
            scope.spawn(move || {
                for (k, x) in part.iter_mut().enumerate() {
                    f(c * chunk + k, x);
                }
            });
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_item_is_computed_once_with_its_own_index() {
        for n in [0, 1, MIN_ITEMS_PER_THREAD * 2 + 3, MIN_ITEMS_PER_THREAD * 5] {
            let mut items = vec![0usize; n];
            in_parallel(&mut items, |i, x| *x += i * 3 + 1);
            assert!(
                items.iter().enumerate().all(|(i, &x)| x == i * 3 + 1),
                "{n}"
            );
        }
    }
}
