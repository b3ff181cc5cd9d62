//! A process-wide cache of matrices that depend only on (band, basis, legacy).
//!
//! The value is built outside the lock, so two threads asking at once may both build
//! it; the first one stored wins and both get equal matrices. Building outside the lock
//! also means a failed or panicking build cannot poison the map, and a poisoned lock
//! (a panic elsewhere while holding it) still holds only complete entries, so it is
//! used as is.
use std::collections::HashMap;
use std::hash::Hash;
use std::sync::{Arc, Mutex, OnceLock};

use crate::Result;
use crate::glyph::sh::ShBasis;

/// (band, basis, legacy) as a hashable key (`ShBasis` itself is not `Hash`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) struct BasisKey {
    band: u32,
    descoteaux: bool,
    legacy: bool,
}

impl BasisKey {
    pub fn new(band: u32, basis: ShBasis, legacy: bool) -> Self {
        Self {
            band,
            descoteaux: basis == ShBasis::Descoteaux07,
            legacy,
        }
    }
}

pub(super) type Cache<K, T> = OnceLock<Mutex<HashMap<K, Arc<T>>>>;

/// The cached value for `key`, built with `build` on first use.
pub(super) fn cached<K: Hash + Eq, T>(
    cache: &Cache<K, T>,
    key: K,
    build: impl FnOnce() -> Result<T>,
) -> Result<Arc<T>> {
    let map = cache.get_or_init(|| Mutex::new(HashMap::new()));
    let lookup = map
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
        .get(&key)
        .cloned();
    if let Some(found) = lookup {
        return Ok(found);
    }
    let built = Arc::new(build()?);
    let mut guard = map.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    Ok(guard.entry(key).or_insert(built).clone())
}
