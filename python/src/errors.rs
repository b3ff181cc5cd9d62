//! glyphcast's errors as Python exceptions: bad input (a scene, an array, an option) is a
//! `ValueError`, a file that cannot be read an `OSError`, host memory a `MemoryError`,
//! and the device (Vulkan, validation, GPU memory) a `RuntimeError`; the message is the
//! one the CLI prints.
use glyphcast::Error;
use pyo3::PyErr;
use pyo3::exceptions::{PyMemoryError, PyOSError, PyRuntimeError, PyValueError};

/// The Python exception for `err`.
pub fn to_py(err: Error) -> PyErr {
    let message = err.to_string();
    match err {
        Error::Input { .. } | Error::Invalid(_) | Error::Usage(_) => PyValueError::new_err(message),
        Error::Io { .. } => PyOSError::new_err(message),
        Error::OutOfMemory(_) => PyMemoryError::new_err(message),
        Error::Vulkan { .. } | Error::Setup(_) | Error::Allocation(_) | Error::Validation(_) => {
            PyRuntimeError::new_err(message)
        }
    }
}

/// A `ValueError` naming `what`.
pub fn value_error(what: &str, message: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("{what}: {message}"))
}
