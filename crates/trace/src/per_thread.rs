//! Working memory kept per worker thread from one piece of work to the
//! next.

use crossbeam_utils::CachePadded;
use std::sync::Mutex;

/// One `T` per thread of the current rayon pool, made on first use and
/// kept from one piece of work to the next: working memory (a
/// [`Scratch`](crate::Scratch) is sized by the body count, and a check's
/// lists grow to their size anew, their pages faulted in again) is made
/// once a job, not once per piece or per split of a parallel iterator.
/// Each is made by its own thread on first use, so that its heap blocks
/// come from that thread's arena, and each sits on cache lines of its
/// own: workers that wrote to one line (a small vector, or neighbouring
/// vector headers) made two threads barely faster than one.
pub struct PerThread<T> {
    slots: Vec<CachePadded<Mutex<Option<T>>>>,
}

impl<T> Default for PerThread<T> {
    fn default() -> PerThread<T> {
        PerThread::new()
    }
}

impl<T> PerThread<T> {
    /// A slot for each thread of the current pool.
    pub fn new() -> PerThread<T> {
        PerThread {
            slots: (0..rayon::current_num_threads())
                .map(|_| CachePadded::new(Mutex::new(None)))
                .collect(),
        }
    }

    /// Run `work` with the calling thread's `T`, made by `make` on its
    /// first use. `work` must not wait on other work of the pool (a
    /// parallel iterator of its own): the thread could take up a piece
    /// that asks for the slot it holds.
    #[inline]
    pub fn with<R>(&self, make: impl FnOnce() -> T, work: impl FnOnce(&mut T) -> R) -> R {
        let i = rayon::current_thread_index().unwrap_or(0) % self.slots.len();
        let mut slot = self.slots[i].lock().unwrap_or_else(|e| e.into_inner());
        work(slot.get_or_insert_with(make))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn each_thread_makes_its_value_once() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let made = AtomicUsize::new(0);
        let sums = pool.install(|| {
            let per_thread = PerThread::new();
            let mut sums = Vec::new();
            for _ in 0..4 {
                use rayon::prelude::*;
                let total: usize = (0..1000)
                    .into_par_iter()
                    .map(|k| {
                        let make = || {
                            made.fetch_add(1, Ordering::Relaxed);
                            Vec::new()
                        };
                        per_thread.with(make, |seen: &mut Vec<usize>| {
                            seen.push(k);
                            k
                        })
                    })
                    .sum();
                sums.push(total);
            }
            sums
        });
        assert_eq!(sums, vec![499_500; 4]);
        assert!((1..=3).contains(&made.load(Ordering::Relaxed)));
    }
}
