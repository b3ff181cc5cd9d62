//! One error type for the whole library. Input problems name the file and the field;
//! Vulkan failures name the call that failed; options the library refuses name the
//! [`Setting`], which each front end spells its way (`setting`).
use ash::vk;
use std::fmt;

mod setting;

pub use setting::spell as spell_mentions;
pub use setting::{Mention, Setting, spell as spell_settings};

/// The crate's result type, with [`Error`] as the default error.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Every failure the library reports; the `Display` text is the one-line message, with
/// the options it names in the library's words ([`Setting::name`]); a front end shows
/// [`Error::spelled`] instead, with its own names for them.
///
/// Any message may mention settings ([`Setting::mention`]); `Display` and
/// [`Error::spelled`] are therefore written by hand rather than derived: the one
/// formatting of the variants ([`Error::spelled`]) takes the spelling.
#[derive(Debug)]
pub enum Error {
    /// A scene or data file that does not follow the format.
    Input {
        /// The file the bad value came from.
        file: String,
        /// The field, key or record that is wrong.
        field: String,
        /// What is wrong and what was expected.
        message: String,
    },
    /// Reading or writing a file failed.
    Io {
        /// The file or directory involved.
        path: String,
        /// The operating system's (or the codec's) message.
        message: String,
    },
    /// A Vulkan call returned an error code.
    Vulkan {
        /// The name of the failing call (e.g. `vkCreateBuffer`).
        call: &'static str,
        /// The code the call returned.
        result: vk::Result,
    },
    /// The Vulkan loader or a required feature, layer or device is missing.
    Setup(String),
    /// GPU memory allocation failed.
    Allocation(gpu_allocator::AllocationError),
    /// Host memory for a large buffer (an image's read-back, a volume's voxels, an
    /// encoded output) could not be allocated; the message says what needed it.
    OutOfMemory(String),
    /// The validation layer reported errors (only when validation is on).
    Validation(Vec<String>),
    /// An option's value the library refuses, or options that do not go together (also
    /// where the data decide, as a lightbox of more slices than the volume has):
    /// `setting` is the option the caller should change (the command line reports it as
    /// a usage error, exit code 2; Python raises ValueError naming the keyword). Shown as
    /// `SETTING[ VALUE]: MESSAGE`.
    Setting {
        /// The option.
        setting: Setting,
        /// Its value as given, if the message shows it (quoted where it is text).
        value: Option<String>,
        /// What is wrong and what is accepted.
        message: String,
    },
    /// A request that cannot be carried out as asked (settings, sizes, limits).
    Invalid(String),
    /// A request that asks for something contradictory or beyond the device (exit code 2
    /// on the command line, as for clap's own usage errors).
    Usage(String),
}

impl From<gpu_allocator::AllocationError> for Error {
    fn from(err: gpu_allocator::AllocationError) -> Self {
        Error::Allocation(err)
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Allocation(err) => Some(err),
            _ => None,
        }
    }
}

impl fmt::Display for Error {
    /// The message with settings in the library's words ([`Setting::plain`]).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.spelled(&|setting, value| setting.plain(value)))
    }
}

impl Error {
    /// A [`Error::Setting`]: `setting` is refused, for the reason `message`.
    pub fn setting(setting: Setting, message: impl Into<String>) -> Self {
        Error::Setting {
            setting,
            value: None,
            message: message.into(),
        }
    }

    /// A [`Error::Setting`] that shows the value refused (`step 0.0001: must be ...`).
    pub fn setting_value(
        setting: Setting,
        value: impl fmt::Display,
        message: impl Into<String>,
    ) -> Self {
        Error::Setting {
            setting,
            value: Some(value.to_string()),
            message: message.into(),
        }
    }

    /// The one-line message, every setting it names (the subject of an
    /// [`Error::Setting`] and the [`Mention`]s in any text) spelled by `spell(setting,
    /// value)`: the command line gives `--step 0.0001`, the Python module `step=0.0001`.
    pub fn spelled(&self, spell: &dyn Fn(Setting, Option<&str>) -> String) -> String {
        let text = match self {
            Error::Input {
                file,
                field,
                message,
            } => format!("{file}: {field}: {message}"),
            Error::Io { path, message } => format!("{path}: {message}"),
            Error::Vulkan { call, result } => format!("Vulkan {call} failed: {result}"),
            Error::Setup(message) => format!("Vulkan setup: {message}"),
            Error::Allocation(err) => format!("GPU memory: {err}"),
            Error::OutOfMemory(message) => format!("out of memory: {message}"),
            Error::Validation(errors) => format!(
                "Vulkan validation reported {} error(s); first: {}",
                errors.len(),
                errors.first().map(String::as_str).unwrap_or("")
            ),
            Error::Setting {
                setting,
                value,
                message,
            } => {
                let subject = match value {
                    Some(value) => setting.with(value),
                    None => setting.mention(),
                };
                format!("{subject}: {message}")
            }
            Error::Invalid(message) | Error::Usage(message) => message.clone(),
        };
        setting::spell(&text, spell)
    }

    /// The setting an [`Error::Setting`] is about.
    pub fn setting_of(&self) -> Option<Setting> {
        match self {
            Error::Setting { setting, .. } => Some(*setting),
            _ => None,
        }
    }

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
    fn setting_errors_name_the_setting_in_each_front_ends_words() {
        use super::Setting;
        let step = Error::setting_value(Setting::Step, 0.0001, "must be in 0.001 to 2");
        assert_eq!(step.setting_of(), Some(Setting::Step));
        assert_eq!(step.to_string(), "step 0.0001: must be in 0.001 to 2");
        let keyword = |s: Setting, v: Option<&str>| match v {
            Some(v) => format!("{}={v}", s.name().replace(' ', "_")),
            None => s.name().replace(' ', "_"),
        };
        assert_eq!(step.spelled(&keyword), "step=0.0001: must be in 0.001 to 2");
        // Mentions in any variant's text, the field of an input error included.
        let input = Error::input(
            "fod.nii",
            Setting::Lmax.mention().to_string(),
            format!("3 is odd; see {}", Setting::MinAmplitude.with(0.5)),
        );
        assert_eq!(input.setting_of(), None);
        assert_eq!(
            input.to_string(),
            "fod.nii: lmax: 3 is odd; see minimum amplitude 0.5"
        );
        assert_eq!(
            input.spelled(&keyword),
            "fod.nii: lmax: 3 is odd; see minimum_amplitude=0.5"
        );
        for err in [&step, &input] {
            assert!(!err.to_string().contains("--"), "{err}");
            assert!(!err.to_string().chars().any(char::is_control), "{err}");
        }
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
