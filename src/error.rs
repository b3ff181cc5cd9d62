//! One error type for the whole library. Input problems name the file and the field;
//! Vulkan failures name the call that failed.
use ash::vk;

/// The crate's result type, with [`Error`] as the default error.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Every failure the library reports; the `Display` text is the one-line message users see.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A scene or data file that does not follow the format.
    #[error("{file}: {field}: {message}")]
    Input {
        /// The file the bad value came from.
        file: String,
        /// The field, key or record that is wrong.
        field: String,
        /// What is wrong and what was expected.
        message: String,
    },
    /// Reading or writing a file failed.
    #[error("{path}: {message}")]
    Io {
        /// The file or directory involved.
        path: String,
        /// The operating system's (or the codec's) message.
        message: String,
    },
    /// A Vulkan call returned an error code.
    #[error("Vulkan {call} failed: {result}")]
    Vulkan {
        /// The name of the failing call (e.g. `vkCreateBuffer`).
        call: &'static str,
        /// The code the call returned.
        result: vk::Result,
    },
    /// The Vulkan loader or a required feature, layer or device is missing.
    #[error("Vulkan setup: {0}")]
    Setup(String),
    /// GPU memory allocation failed.
    #[error("GPU memory: {0}")]
    Allocation(#[from] gpu_allocator::AllocationError),
    /// Host memory for a large buffer (an image's read-back, a volume's voxels, an
    /// encoded output) could not be allocated; the message says what needed it.
    #[error("out of memory: {0}")]
    OutOfMemory(String),
    /// The validation layer reported errors (only when validation is on).
    #[error("Vulkan validation reported {} error(s); first: {}", .0.len(), .0.first().map(String::as_str).unwrap_or(""))]
    Validation(Vec<String>),
    /// A request that cannot be carried out as asked (settings, sizes, limits).
    #[error("{0}")]
    Invalid(String),
    /// A command line that asks for something contradictory (exit code 2, as for
    /// clap's own usage errors).
    #[error("{0}")]
    Usage(String),
}

impl Error {
    /// An [`Error::Input`] for `field` of `file`.
    pub fn input(
        file: impl Into<String>,
        field: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        Error::Input {
            file: file.into(),
            field: field.into(),
            message: message.into(),
        }
    }

    /// An [`Error::Io`] for `path`, with `err`'s message.
    pub fn io(path: impl AsRef<std::path::Path>, err: impl std::fmt::Display) -> Self {
        Error::Io {
            path: path.as_ref().display().to_string(),
            message: err.to_string(),
        }
    }

    /// Whether the error is a lack of memory, host or GPU: a caller may free some and
    /// try again, or ask for less (a smaller image, fewer glyphs).
    pub fn is_out_of_memory(&self) -> bool {
        match self {
            Error::OutOfMemory(_) => true,
            Error::Allocation(err) => {
                matches!(err, gpu_allocator::AllocationError::OutOfMemory)
            }
            Error::Vulkan { result, .. } => matches!(
                *result,
                vk::Result::ERROR_OUT_OF_HOST_MEMORY | vk::Result::ERROR_OUT_OF_DEVICE_MEMORY
            ),
            _ => false,
        }
    }

    /// Whether the device was lost (driver reset, GPU hang): every object made with it
    /// must be dropped and the device created again.
    pub fn is_device_lost(&self) -> bool {
        matches!(
            self,
            Error::Vulkan {
                result: vk::Result::ERROR_DEVICE_LOST,
                ..
            }
        )
    }

    /// The same error as a usage error (exit code 2) when it is about the request itself
    /// ([`Error::Invalid`]); for command-line checks whose library code cannot know that
    /// its settings came from flags. Other kinds are returned unchanged.
    pub fn into_usage(self) -> Self {
        match self {
            Error::Invalid(message) => Error::Usage(message),
            other => other,
        }
    }
}

/// Characters of user text quoted in a message before it is cut short.
const QUOTED_CHARS: usize = 60;

/// User text (a scene key, a name, a value) as a message may quote it: on one line, with
/// control characters escaped (`\n`, `\u{1b}`) and anything past [`QUOTED_CHARS`]
/// characters replaced by a count, so that a hostile or mistaken input cannot forge
/// lines, move the terminal's cursor or flood the screen.
pub fn quoted(text: &str) -> String {
    let mut out = String::new();
    for (count, c) in text.chars().enumerate() {
        if count == QUOTED_CHARS {
            out.push_str(&format!("... ({} bytes in all)", text.len()));
            break;
        }
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

/// Attach the name of the failing Vulkan call to a `vk::Result`.
pub trait VkContext<T> {
    /// The result with a Vulkan error turned into [`Error::Vulkan`] naming `call`.
    fn vk(self, call: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for std::result::Result<T, vk::Result> {
    fn vk(self, call: &'static str) -> Result<T> {
        self.map_err(|result| Error::Vulkan { call, result })
    }
}

#[cfg(test)]
mod tests {
    use super::{Error, quoted, vk};

    #[test]
    fn memory_and_device_loss_are_told_apart_from_other_errors() {
        let host = Error::OutOfMemory("a 16384 x 16384 read-back".into());
        let gpu = Error::Allocation(gpu_allocator::AllocationError::OutOfMemory);
        let device_memory = Error::Vulkan {
            call: "vkAllocateMemory",
            result: vk::Result::ERROR_OUT_OF_DEVICE_MEMORY,
        };
        let lost = Error::Vulkan {
            call: "vkQueueSubmit",
            result: vk::Result::ERROR_DEVICE_LOST,
        };
        let input = Error::input("a.nii", "dim", "too large");
        for err in [&host, &gpu, &device_memory] {
            assert!(err.is_out_of_memory() && !err.is_device_lost(), "{err}");
        }
        assert!(lost.is_device_lost() && !lost.is_out_of_memory());
        assert!(!input.is_out_of_memory() && !input.is_device_lost());
        assert!(host.to_string().starts_with("out of memory: "));
    }

    #[test]
    fn quoted_text_is_one_short_line() {
        assert_eq!(quoted("scale"), "scale");
        assert_eq!(quoted("a\nb\u{1b}[2J"), "a\\nb\\u{1b}[2J");
        let long = "k".repeat(2_000_000);
        let shown = quoted(&long);
        assert!(shown.len() < 100, "{shown}");
        assert!(shown.ends_with("(2000000 bytes in all)"), "{shown}");
        assert_eq!(quoted("é".repeat(60).as_str()), "é".repeat(60));
    }
}
