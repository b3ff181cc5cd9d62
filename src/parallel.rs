//! Work spread over every core with scoped threads, results in input order.
use crate::{Error, Result};

/// `f` of every item, computed on `available_parallelism` scoped threads over contiguous
/// chunks, in the order of `items`; the first error (in item order) wins. `what` names
/// the work in the error of a thread that panicked.
pub fn map_chunks<I, T, F>(items: &[I], what: &str, f: F) -> Result<Vec<T>>
where
    I: Sync,
    T: Send,
    F: Fn(&I) -> Result<T> + Sync,
{
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    let chunk = items.len().div_ceil(threads).max(1);
    let f = &f;
    let parts: Vec<Result<Vec<T>>> = std::thread::scope(|scope| {
        let workers: Vec<_> = items
            .chunks(chunk)
            .map(|part| scope.spawn(move || part.iter().map(f).collect()))
            .collect();
        workers
            .into_iter()
            .map(|w| {
                w.join()
                    .unwrap_or_else(|_| Err(Error::Invalid(format!("{what}: a thread failed"))))
            })
            .collect()
    });
    let mut out = Vec::with_capacity(items.len());
    for part in parts {
        out.extend(part?);
    }
    Ok(out)
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
                Err(Error::Invalid(format!("item {i}")))
            } else {
                Ok(*i)
            }
        });
        assert!(matches!(failed, Err(Error::Invalid(m)) if m == "item 700"));
        assert!(
            map_chunks(&[] as &[u32], "nothing", |i| Ok(*i))
                .unwrap()
                .is_empty()
        );
    }
}
