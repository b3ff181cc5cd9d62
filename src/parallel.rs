//! Work spread over every core with scoped threads, results in input order.
use crate::{Error, Result};
use std::sync::atomic::{AtomicUsize, Ordering};

/// How far a long preparation has come, for a progress display on another thread: the
/// current phase's name, its items done and its item count.
#[derive(Debug, Default)]
pub struct Progress {
    phase: std::sync::Mutex<&'static str>,
    done: AtomicUsize,
    total: AtomicUsize,
}

impl Progress {
    /// Starts a phase of `total` items.
    pub fn start(&self, phase: &'static str, total: usize) {
        if let Ok(mut p) = self.phase.lock() {
            *p = phase;
        }
        self.done.store(0, Ordering::Relaxed);
        self.total.store(total, Ordering::Relaxed);
    }

    /// Counts `items` more done in the current phase (for work done in blocks).
    pub fn advance(&self, items: usize) {
        self.done.fetch_add(items, Ordering::Relaxed);
    }

    /// The phase's name and the fraction of its items done.
    pub fn get(&self) -> (&'static str, f64) {
        let phase = self.phase.lock().map_or("", |p| *p);
        let total = self.total.load(Ordering::Relaxed);
        let done = self.done.load(Ordering::Relaxed);
        (
            phase,
            if total == 0 {
                0.0
            } else {
                (done as f64 / total as f64).min(1.0)
            },
        )
    }
}

/// `f` of every item, computed on `available_parallelism` scoped threads over contiguous
/// chunks, in the order of `items`; the first error (in item order) wins. `what` names
/// the work in the error of a thread that panicked.
pub fn map_chunks<I, T, F>(items: &[I], what: &'static str, f: F) -> Result<Vec<T>>
where
    I: Sync,
    T: Send,
    F: Fn(&I) -> Result<T> + Sync,
{
    map_chunks_with_progress(items, what, None, f)
}

/// Lists at most this long are mapped on the calling thread.
const INLINE_ITEMS: usize = 16;

/// [`map_chunks`], which also starts a phase named `what` in `progress` and counts the
/// items done there.
pub fn map_chunks_with_progress<I, T, F>(
    items: &[I],
    what: &'static str,
    progress: Option<&Progress>,
    f: F,
) -> Result<Vec<T>>
where
    I: Sync,
    T: Send,
    F: Fn(&I) -> Result<T> + Sync,
{
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    let chunk = items.len().div_ceil(threads).max(1);
    if let Some(p) = progress {
        p.start(what, items.len());
    }
    let f = &|item: &I| {
        let result = f(item);
        if let Some(p) = progress {
            p.done.fetch_add(1, Ordering::Relaxed);
        }
        result
    };
    // A few items cost less than starting threads (a scene of many one-glyph sets).
    if items.len() <= INLINE_ITEMS {
        return items.iter().map(f).collect();
    }
    let parts: Vec<Result<Vec<T>>> = std::thread::scope(|scope| {
        let workers: Vec<_> = items
            .chunks(chunk)
            .map(|part| scope.spawn(move || part.iter().map(f).collect()))
            .collect();
        workers
            .into_iter()
            .map(|w| w.join().unwrap_or_else(|_| Err(Error::Thread { what })))
            .collect()
    });
    let mut out = Vec::with_capacity(items.len());
    for part in parts {
        out.extend(part?);
    }
    Ok(out)
}

/// Fills `out`, `width` values per item, with `f(item, its width values)` on
/// `available_parallelism` scoped threads over contiguous chunks. Unlike [`map_chunks`],
/// nothing is allocated for the results: the caller owns the buffer, so work that
/// allocates nothing itself leaves nothing in the workers' allocator arenas (glibc
/// gives each thread an arena of its own, which keeps what is freed there for its later
/// use rather than giving it back). Items past `out.len() / width` are skipped.
pub(crate) fn fill_chunks<I, O, F>(
    items: &[I],
    out: &mut [O],
    width: usize,
    what: &'static str,
    f: F,
) -> Result<()>
where
    I: Sync,
    O: Send,
    F: Fn(&I, &mut [O]) + Sync,
{
    if width == 0 {
        return Ok(());
    }
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    let chunk = items.len().div_ceil(threads).max(1);
    let f = &f;
    let fill = move |part: &[I], out: &mut [O]| {
        for (item, slot) in part.iter().zip(out.chunks_mut(width)) {
            f(item, slot);
        }
    };
    if items.len() <= INLINE_ITEMS {
        fill(items, out);
        return Ok(());
    }
    let panicked = std::thread::scope(|scope| {
        let workers: Vec<_> = items
            .chunks(chunk)
            .zip(out.chunks_mut(chunk * width))
            .map(|(part, out)| scope.spawn(move || fill(part, out)))
            .collect();
        // Every worker joined (not `any`, which stops at the first): the scope panics
        // over a panicked worker left unjoined.
        let panicked = workers
            .into_iter()
            .map(|w| w.join().is_err())
            .filter(|&panicked| panicked)
            .count();
        panicked > 0
    });
    if panicked {
        return Err(Error::Thread { what });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_the_order_and_reports_the_first_error() {
        let items: Vec<u32> = (0..1001).collect();
        let doubled = map_chunks(&items, "doubling", |i| Ok(2 * i)).unwrap();
        assert_eq!(doubled, items.iter().map(|i| 2 * i).collect::<Vec<_>>());
        let failed = map_chunks(&items, "failing", |i| {
            if *i >= 700 {
                Err(Error::data(
                    "item",
                    crate::error::Problem::Count {
                        expected: 0,
                        found: *i as usize,
                    },
                ))
            } else {
                Ok(*i)
            }
        });
        assert!(matches!(
            failed,
            Err(Error::Data {
                problem: crate::error::Problem::Count { found: 700, .. },
                ..
            })
        ));
        let progress = Progress::default();
        map_chunks_with_progress(&items, "counting", Some(&progress), |i| Ok(*i)).unwrap();
        assert_eq!(progress.get(), ("counting", 1.0));
        progress.start("next", 4);
        assert_eq!(progress.get(), ("next", 0.0));
        assert!(
            map_chunks(&[] as &[u32], "nothing", |i| Ok(*i))
                .unwrap()
                .is_empty()
        );
    }

    #[test]
    fn fills_each_items_values_in_place() {
        for count in [0, 5, 1001] {
            let items: Vec<u32> = (0..count).collect();
            let mut out = vec![0u32; 3 * items.len()];
            fill_chunks(&items, &mut out, 3, "filling", |i, slot| {
                for (j, v) in slot.iter_mut().enumerate() {
                    *v = 10 * i + j as u32;
                }
            })
            .unwrap();
            let want: Vec<u32> = items
                .iter()
                .flat_map(|i| (0..3).map(move |j| 10 * i + j))
                .collect();
            assert_eq!(out, want);
        }
        let failed = fill_chunks(&[1u32; 100], &mut [0u32; 100], 1, "panicking", |i, _| {
            assert_ne!(*i, 1, "a worker's panic");
        });
        assert!(matches!(failed, Err(Error::Thread { what: "panicking" })));
    }
}
