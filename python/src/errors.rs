//! glyphcast's errors as Python exceptions: bad input (a scene, an array, an option) is a
//! `ValueError`, a file that cannot be read an `OSError`, host memory a `MemoryError`,
//! and the device (Vulkan, validation, GPU memory) a `RuntimeError`. The message is the
//! CLI's, with every setting it names spelled as this module's keyword
//! (`magnitude_range='1-2': not LOW:HIGH` where the CLI says `--magnitude-range '1-2'`).
use glyphcast::{Error, Setting};
use pyo3::PyErr;
use pyo3::exceptions::{PyMemoryError, PyOSError, PyRuntimeError, PyValueError};

/// The Python exception for `err`.
pub fn to_py(err: Error) -> PyErr {
    let message = err.spelled(&spell);
    match err {
        Error::Io { .. } => PyOSError::new_err(message),
        Error::OutOfMemory { .. } => PyMemoryError::new_err(message),
        Error::Vulkan { .. }
        | Error::Setup { .. }
        | Error::Allocation(_)
        | Error::Validation(_)
        | Error::Thread { .. } => PyRuntimeError::new_err(message),
        // Input, settings, conflicts, limits, data, unsupported requests and calls: the
        // caller's values (new kinds default here: the enum is non_exhaustive).
        _ => PyValueError::new_err(message),
    }
}

/// A `ValueError` naming `what`.
pub fn value_error(what: &str, message: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("{what}: {message}"))
}

/// `setting` as a keyword argument, with its value if any (`step=0.0001`); a switch
/// without a value is written as the keyword that turns it on (`legacy=True`, and
/// `symmetric=False` for the command line's `--nonsymmetric`).
pub fn spell(setting: Setting, value: Option<&str>) -> String {
    match (value, setting.keyword_on()) {
        (Some(value), _) => format!("{}={value}", setting.keyword()),
        (None, Some(on)) => format!("{}={on}", setting.keyword()),
        (None, None) => setting.keyword().to_owned(),
    }
}
