//! One error type for the whole library, with variants a caller can match on: input
//! problems name the file and the field; Vulkan failures the call; options the library
//! refuses name the [`Setting`] (and, for options that do not go together, both sides);
//! limits carry the value and the limit; data the library refuses say which quantity and
//! what was expected. No variant is a bare sentence: the text is made from the fields,
//! once ([`Error::spelled`]), and each front end spells the settings its way.
//! Free text remains where it is the data: a file's field's problem ([`Error::Input`]),
//! a refused setting's reason ([`Error::Setting`]), the operating system's or a solver's
//! own message; settings inside such text are typed pieces of a [`Message`].
use ash::vk;
use std::fmt;

mod message;
mod setting;

pub use message::{Message, Piece};
pub use setting::{Setting, SettingName};

/// The crate's result type, with [`Error`] as the default error.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Every failure the library reports; the `Display` text is the one-line message, with
/// the options it names in the library's words ([`Setting::name`]); a front end shows
/// [`Error::spelled`] instead, with its own names for them.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// A scene or data file that does not follow the format, or data that cannot be
    /// drawn as asked.
    Input {
        /// The file the bad value came from.
        file: String,
        /// The field, key or record that is wrong.
        field: String,
        /// What is wrong and what was expected.
        message: Message,
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
    /// Something the machine lacks: the Vulkan loader or driver, a layer, a device with
    /// the features needed, a window system, a font.
    Setup {
        /// What is missing, as a noun (`the Vulkan loader (libvulkan.so.1)`).
        missing: &'static str,
        /// What was found instead, or the cause's own message.
        found: Option<String>,
    },
    /// GPU memory allocation failed.
    Allocation(gpu_allocator::AllocationError),
    /// Host memory for a large buffer (an image's read-back, a volume's voxels, an
    /// encoded output) could not be allocated.
    OutOfMemory {
        /// What needed the memory (`the image's read-back`).
        what: &'static str,
        /// The file it was for, if any.
        file: Option<String>,
        /// How many bytes were asked for, where known.
        bytes: Option<u64>,
        /// The settings that decide the size (the image's width and height), if any:
        /// asking for less through them is the remedy.
        settings: &'static [Setting],
    },
    /// The validation layer reported errors (only when validation is on).
    Validation(Vec<String>),
    /// An option's value the library refuses (also where the data decide, as a lightbox
    /// of more slices than the volume has): `setting` is the option the caller should
    /// change (the command line reports it as a usage error, exit code 2; Python raises
    /// ValueError naming the keyword). Shown as `SETTING[ VALUE]: MESSAGE`.
    Setting {
        /// The option.
        setting: Setting,
        /// Its value as given, if the message shows it (quoted where it is text).
        value: Option<String>,
        /// What is wrong and what is accepted.
        message: Message,
    },
    /// Two options that do not go together, or one that needs another (a usage error, as
    /// [`Error::Setting`]).
    Conflict {
        /// The option refused.
        option: Choice,
        /// The option it clashes with or needs.
        with: Choice,
        /// How the two relate.
        relation: Relation,
    },
    /// A front end's own option refused, in that front end's spelling (`--script`):
    /// options no library request has, checked by the front end itself (a usage error).
    Flag {
        /// The option, as the front end spells it.
        flag: &'static str,
        /// What is wrong and what is accepted.
        message: Message,
    },
    /// A size beyond a limit (the library's or the device's).
    Limit {
        /// The quantity, as a noun (`image side in pixels`).
        what: &'static str,
        /// Its value.
        value: u64,
        /// The largest value allowed.
        limit: u64,
        /// The settings that decide the value; when there are any, the request is what
        /// should change (a usage error), otherwise the data are too large.
        settings: &'static [Setting],
    },
    /// Values handed to the library (coefficients, pixels, directions) that it cannot
    /// use.
    Data {
        /// The quantity, as a noun (`SH coefficients`).
        what: &'static str,
        /// What is wrong with it.
        problem: Problem,
    },
    /// A combination the library has no code or shader for.
    Unsupported {
        /// What was asked for.
        what: Asked,
        /// The part of the library (a pass, a path, a model) that does not take it.
        by: Piece,
    },
    /// A call out of order or with an argument its caller should not have given (a
    /// programming error of the caller, not a user's).
    Call {
        /// The function called.
        call: &'static str,
        /// What it expected (`set_glyphs first`).
        expected: &'static str,
    },
    /// A frame-in-flight index beyond the frames the renderer was made with.
    FrameIndex {
        /// The index given.
        index: usize,
        /// The frames in flight.
        frames: usize,
    },
    /// A numerical step failed (a solver, a decomposition).
    Numerical {
        /// The step (`CSD's quadratic programme`).
        step: &'static str,
        /// The solver's own message.
        detail: String,
    },
    /// An output's file name that does not end as the files of its format do (`-o
    /// out.jpg` for a PNG): a usage error naming the option.
    OutputName {
        /// The option that names the output, as the front end spells it (`-o/--output`).
        option: &'static str,
        /// The name given.
        path: String,
        /// The format written (`PNG`).
        format: String,
        /// The endings its files have (`.png`).
        endings: Vec<String>,
    },
    /// Two outputs of one request that name the same file (a usage error).
    SameOutput {
        /// The first output's path.
        first: String,
        /// The second output's path, which names the same file.
        second: String,
    },
    /// An output that names an input file of the same request, or an output folder
    /// that holds one (a usage error: writing it would destroy the input).
    OutputIsInput {
        /// The output's path.
        output: String,
        /// The input's path, which names the same file (or lies inside the folder).
        input: String,
        /// Whether the output is a folder.
        folder: bool,
    },
    /// An output folder holding an entry that no earlier output of the same command
    /// wrote (a usage error: glyphcast replaces only what it wrote).
    ForeignEntry {
        /// The folder.
        folder: String,
        /// One entry in it that is not the command's.
        entry: String,
        /// What to do instead.
        remedy: &'static str,
    },
    /// An environment variable the library reads holds a value it cannot use.
    Environment {
        /// The variable.
        variable: &'static str,
        /// Its value, quoted.
        value: String,
        /// What it should hold.
        expected: &'static str,
    },
    /// A tensor layout the device or a pass cannot draw: the layout, and why. Shown as
    /// `a symmetric tensor of order N: ERROR`.
    Layout {
        /// The layout.
        layout: LayoutName,
        /// What stands in its way.
        error: Box<Error>,
    },
    /// One item of a list (a glyph of a set, a glyph set of a scene) that cannot be
    /// used: which one, and why. Shown as `WHAT INDEX: ERROR`.
    Item {
        /// What the items are, singular (`glyph set`).
        what: &'static str,
        /// The item's index in its list.
        index: usize,
        /// What is wrong with it.
        error: Box<Error>,
    },
    /// A worker thread stopped without a result (it panicked).
    Thread {
        /// The work it was doing.
        what: &'static str,
    },
}

/// One side of an [`Error::Conflict`]: a library [`Setting`], or a front end's own flag
/// in that front end's spelling, with the value given where it matters.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Choice {
    /// A setting of the library's requests.
    Setting(Setting, Option<String>),
    /// A front end's own option (`--script`), spelled by that front end.
    Flag(&'static str),
}

impl From<Setting> for Choice {
    fn from(setting: Setting) -> Self {
        Choice::Setting(setting, None)
    }
}

impl From<Piece> for Choice {
    fn from(piece: Piece) -> Self {
        match piece {
            Piece::Setting(setting, value) => Choice::Setting(setting, value),
            Piece::Text(_) => Choice::Flag("?"),
        }
    }
}

impl From<&'static str> for Choice {
    fn from(flag: &'static str) -> Self {
        Choice::Flag(flag)
    }
}

/// How the two options of an [`Error::Conflict`] relate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Relation {
    /// Give one or the other, not both.
    Exclusive,
    /// The option needs the other one.
    Requires,
    /// The option does not go with the other one.
    Excludes,
}

/// What is wrong with the values of an [`Error::Data`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Problem {
    /// The wrong number of values.
    Count {
        /// How many were expected.
        expected: usize,
        /// How many were given.
        found: usize,
    },
    /// A value at `index` that is NaN or infinite.
    NotFinite {
        /// Its index.
        index: usize,
        /// The value.
        value: f64,
    },
    /// A value outside the range the library takes.
    OutOfRange {
        /// The value.
        value: f64,
        /// The smallest value taken.
        min: f64,
        /// The largest value taken.
        max: f64,
    },
    /// An odd value where only even ones are taken (an SH band, a tensor order).
    Odd {
        /// The value.
        value: u64,
    },
    /// Too few independent values to determine the unknowns (a fit's design).
    Underdetermined {
        /// The independent values (directions, rank).
        known: usize,
        /// The unknowns.
        unknowns: usize,
    },
    /// Nothing to work with.
    Empty,
    /// A value that must be above zero.
    NotPositive {
        /// The value.
        value: f64,
    },
    /// Every value is zero.
    AllZero,
    /// A vector (a direction) at `index` that is zero or not finite.
    ZeroVector {
        /// Its index.
        index: usize,
    },
    /// Directions that determine fewer of the unknowns than there are (too many of them
    /// on one great circle).
    RankDeficient {
        /// The unknowns determined (the design's rank).
        rank: usize,
        /// The unknowns.
        unknowns: usize,
    },
    /// Values too few or too alike to determine the unknowns in floating point.
    IllConditioned {
        /// The values given.
        known: usize,
        /// The unknowns.
        unknowns: usize,
        /// An estimate of the design's condition number.
        condition: f64,
    },
    /// A matrix that should be orthogonal (a rotation) and is not.
    NotOrthogonal {
        /// The largest entry of |R^T R - I|.
        deviation: f64,
    },
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Problem::Count { expected, found } => write!(f, "expected {expected}, found {found}"),
            Problem::NotFinite { index, value } => {
                write!(f, "value {index} is not finite ({value})")
            }
            Problem::OutOfRange { value, min, max } => {
                write!(f, "{value} is outside {min} to {max}")
            }
            Problem::Odd { value } => write!(f, "{value} is odd; only even values are taken"),
            Problem::Underdetermined { known, unknowns } => write!(
                f,
                "{known} independent values cannot determine {unknowns} unknowns"
            ),
            Problem::Empty => f.write_str("none given"),
            Problem::NotPositive { value } => write!(f, "{value} is not above zero"),
            Problem::AllZero => f.write_str("every value is zero"),
            Problem::ZeroVector { index } => write!(f, "vector {index} is zero or not finite"),
            Problem::RankDeficient { rank, unknowns } => write!(
                f,
                "they determine only {rank} of the {unknowns} unknowns (too many on one great \
                 circle?)"
            ),
            Problem::IllConditioned {
                known,
                unknowns,
                condition,
            } => write!(
                f,
                "{known} do not determine the {unknowns} unknowns (condition number estimate \
                 {condition:.3e})"
            ),
            Problem::NotOrthogonal { deviation } => {
                write!(f, "not orthogonal: |R^T R - I| = {deviation:.3e}")
            }
        }
    }
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

/// A tensor layout as errors name it: its order and whether it is symmetric (made from a
/// `glyph::TensorLayout` with `into()`). Shown as `a symmetric tensor of order N`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LayoutName {
    /// The tensor's order.
    pub order: u32,
    /// Whether the tensor is symmetric.
    pub symmetric: bool,
}

impl fmt::Display for LayoutName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kind = if self.symmetric {
            "symmetric"
        } else {
            "non-symmetric"
        };
        write!(f, "a {kind} tensor of order {}", self.order)
    }
}

/// What a part of the library was asked for and has no code or shader for
/// ([`Error::Unsupported`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Asked {
    /// Glyphs of a tensor layout (a ray-casting shader, an evaluation shader).
    Layout(LayoutName),
    /// Ellipsoid glyphs (`--glyph ellipsoid`), ray-cast in closed form.
    Ellipsoids,
    /// Reciprocal glyphs (scene `shape` `reciprocal`, r = 1/|f|), which the exact method
    /// alone ray-casts.
    Reciprocal,
    /// Plane glyphs (scene `shape` `plane-min`/`plane-max`, r = 1/λ), which the exact
    /// method alone ray-casts.
    Plane,
    /// Ratio glyphs (scene `shape` `ratio-min`/`ratio-max`, r = |λ/Q|), which the exact
    /// method alone ray-casts.
    Ratio,
    /// An intersection method: the method setting with its value
    /// (`Setting::Method.with(method)`), spelled by the front end.
    Method(Piece),
}

impl Asked {
    /// The words for what was asked, its setting spelled by `spell`.
    fn spelled(&self, spell: Spell<'_>) -> String {
        match self {
            Asked::Layout(layout) => layout.to_string(),
            Asked::Ellipsoids => "ellipsoid glyphs, which are ray-cast in closed form (not \
                                  tessellated, not marched)"
                .to_owned(),
            Asked::Reciprocal => "reciprocal glyphs (shape reciprocal, r = 1/|f|), which only \
                                  the exact method draws (not tessellated, not marched, no \
                                  offset)"
                .to_owned(),
            Asked::Plane => "plane glyphs (shape plane-min or plane-max, r = 1/λ), which \
                             only the exact method draws (not tessellated, not marched, no \
                             offset)"
                .to_owned(),
            Asked::Ratio => "ratio glyphs (shape ratio-min or ratio-max, r = |λ/Q|), which \
                             only the exact method draws (not tessellated, not marched, no \
                             offset)"
                .to_owned(),
            Asked::Method(method) => piece(method, spell),
        }
    }
}

impl fmt::Display for Error {
    /// The message with settings in the library's words ([`Setting::plain`]).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.spelled(&|setting, value| setting.plain(value)))
    }
}

/// A front end's spelling of a setting and its value.
pub(crate) type Spell<'a> = &'a dyn Fn(Setting, Option<&str>) -> String;

fn choice(choice: &Choice, spell: Spell<'_>) -> String {
    match choice {
        Choice::Setting(setting, value) => spell(*setting, value.as_deref()),
        Choice::Flag(flag) => (*flag).to_owned(),
    }
}

/// Settings spelled and joined with `/` (`--width/--height`).
fn spelled_list(settings: &[Setting], spell: Spell<'_>) -> String {
    let names: Vec<String> = settings.iter().map(|s| spell(*s, None)).collect();
    names.join("/")
}

fn piece(piece: &Piece, spell: Spell<'_>) -> String {
    match piece {
        Piece::Setting(setting, value) => spell(*setting, value.as_deref()),
        Piece::Text(text) => text.clone(),
    }
}

impl Error {
    /// A [`Error::Setting`]: `setting` is refused, for the reason `message`.
    pub fn setting(setting: Setting, message: impl Into<Message>) -> Self {
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
        message: impl Into<Message>,
    ) -> Self {
        Error::Setting {
            setting,
            value: Some(value.to_string()),
            message: message.into(),
        }
    }

    /// An [`Error::Conflict`]: `option` stands in `relation` to `with`.
    pub fn conflict(
        option: impl Into<Choice>,
        relation: Relation,
        with: impl Into<Choice>,
    ) -> Self {
        Error::Conflict {
            option: option.into(),
            with: with.into(),
            relation,
        }
    }

    /// An [`Error::Data`] about `what`.
    pub fn data(what: &'static str, problem: Problem) -> Self {
        Error::Data { what, problem }
    }

    /// An [`Error::Setup`]: `missing` is not there; `found` says what is.
    pub fn setup(missing: &'static str, found: impl fmt::Display) -> Self {
        Error::Setup {
            missing,
            found: Some(found.to_string()),
        }
    }

    /// The one-line message, every setting it names spelled by `spell(setting, value)`:
    /// the command line gives `--step 0.0001`, the Python module `step=0.0001`.
    pub fn spelled(&self, spell: Spell<'_>) -> String {
        match self {
            Error::Input {
                file,
                field,
                message,
            } => format!("{file}: {field}: {}", message.spelled(spell)),
            Error::Io { path, message } => format!("{path}: {message}"),
            Error::Vulkan { call, result } => format!("Vulkan {call} failed: {result}"),
            Error::Setup { missing, found } => match found {
                Some(found) => format!("setup: no {missing}: {found}"),
                None => format!("setup: no {missing}"),
            },
            Error::Allocation(err) => format!("GPU memory: {err}"),
            Error::OutOfMemory {
                what,
                file,
                bytes,
                settings,
            } => {
                let file = file
                    .as_deref()
                    .map(|f| format!("{f}: "))
                    .unwrap_or_default();
                let size = bytes.map(|b| format!(" of {} MiB", b.div_ceil(1 << 20)));
                let mut text = format!(
                    "out of memory: {file}{what}{} could not be allocated",
                    size.unwrap_or_default()
                );
                if !settings.is_empty() {
                    text.push_str(&format!(
                        ": ask for less through {}",
                        spelled_list(settings, spell)
                    ));
                }
                text
            }
            Error::Validation(errors) => format!(
                "Vulkan validation reported {} error(s); first: {}",
                errors.len(),
                errors.first().map(String::as_str).unwrap_or("")
            ),
            Error::Setting {
                setting,
                value,
                message,
            } => format!(
                "{}: {}",
                spell(*setting, value.as_deref()),
                message.spelled(spell)
            ),
            Error::Conflict {
                option,
                with,
                relation,
            } => {
                let (a, b) = (choice(option, spell), choice(with, spell));
                match relation {
                    Relation::Exclusive => format!("give either {a} or {b}, not both"),
                    Relation::Requires => format!("{a} needs {b}"),
                    Relation::Excludes => format!("{a} does not go with {b}"),
                }
            }
            Error::Flag { flag, message } => format!("{flag}: {}", message.spelled(spell)),
            Error::Limit {
                what,
                value,
                limit,
                settings,
            } => {
                let mut text = format!("{what} {value} is over the limit of {limit}");
                if !settings.is_empty() {
                    text.push_str(&format!(
                        ": ask for less through {}",
                        spelled_list(settings, spell)
                    ));
                }
                text
            }
            Error::Data { what, problem } => format!("{what}: {problem}"),
            Error::Unsupported { what, by } => {
                format!("{} does not take {}", piece(by, spell), what.spelled(spell))
            }
            Error::Call { call, expected } => format!("{call}: expected {expected}"),
            Error::FrameIndex { index, frames } => {
                format!("frame index {index} of a renderer with {frames} frame(s) in flight")
            }
            Error::Numerical { step, detail } => format!("{step} failed: {detail}"),
            Error::OutputName {
                option,
                path,
                format,
                endings,
            } => {
                // The whole path (the user's own, to find it again), on one line.
                let path_line: String = path
                    .chars()
                    .map(|c| {
                        if c.is_control() {
                            c.escape_default().to_string()
                        } else {
                            c.to_string()
                        }
                    })
                    .collect();
                let mut text = format!(
                    "{option} {path_line}: writes {format}, so the name must end in {}",
                    endings.join(" or ")
                );
                if let Some(ending) = std::path::Path::new(path).extension() {
                    text.push_str(&format!(
                        " (.{} would mislabel the file)",
                        quoted(&ending.to_string_lossy())
                    ));
                }
                text
            }
            Error::SameOutput { first, second } => {
                format!("{first} and {second} name the same file: give each output its own path")
            }
            Error::OutputIsInput {
                output,
                input,
                folder: false,
            } => format!(
                "the output {output} is the input {input}: writing it would destroy the \
                 input; give the output its own path"
            ),
            Error::OutputIsInput { output, input, .. } => format!(
                "the output folder {output} holds the input {input}: give a folder \
                 outside the inputs"
            ),
            Error::ForeignEntry {
                folder,
                entry,
                remedy,
            } => format!(
                "the output folder {folder} holds {entry}, which no earlier run of this \
                 command wrote: {remedy}"
            ),
            Error::Environment {
                variable,
                value,
                expected,
            } => format!("{variable}={value}: expected {expected}"),
            Error::Layout { layout, error } => format!("{layout}: {}", error.spelled(spell)),
            Error::Item { what, index, error } => {
                format!("{what} {index}: {}", error.spelled(spell))
            }
            Error::Thread { what } => format!("{what}: a worker thread stopped without a result"),
        }
    }

    /// The setting an [`Error::Setting`] or [`Error::Conflict`] is about (the first side
    /// of a conflict).
    pub fn setting_of(&self) -> Option<Setting> {
        match self {
            Error::Setting { setting, .. } => Some(*setting),
            Error::Conflict {
                option: Choice::Setting(setting, _),
                ..
            } => Some(*setting),
            _ => None,
        }
    }

    /// Whether the request itself is what should change (a refused setting, options that
    /// clash, a size over a limit the request sets): the command line's exit code 2.
    pub fn is_usage(&self) -> bool {
        match self {
            Error::Setting { .. }
            | Error::Conflict { .. }
            | Error::Flag { .. }
            | Error::OutputName { .. }
            | Error::SameOutput { .. }
            | Error::OutputIsInput { .. }
            | Error::ForeignEntry { .. } => true,
            Error::Item { error, .. } | Error::Layout { error, .. } => error.is_usage(),
            Error::Limit { settings, .. } => !settings.is_empty(),
            _ => false,
        }
    }

    /// This error of drawing the scene read from `file`, naming the file and the glyph
    /// set its data came from (`glyphs[S]`, the scene format's field) when it is about
    /// that data (a glyph whose surface is unbounded, a radius beyond float32); any
    /// other error (a setting's, the device's) is returned as it is.
    pub fn in_scene_file(self, file: impl AsRef<std::path::Path>) -> Error {
        match self {
            Error::Item {
                what: "glyph set",
                index,
                error,
            } if error.is_about_data() => Error::input(
                file.as_ref().display().to_string(),
                format!("glyphs[{index}]"),
                error.to_string(),
            ),
            other => other,
        }
    }

    /// Whether this error is about values the library was given (possibly of an item of
    /// a list), not about a setting or the machine.
    fn is_about_data(&self) -> bool {
        match self {
            Error::Data { .. } => true,
            Error::Item { error, .. } => error.is_about_data(),
            _ => false,
        }
    }

    /// An [`Error::Input`] for `field` of `file`.
    pub fn input(
        file: impl Into<String>,
        field: impl Into<String>,
        message: impl Into<Message>,
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
            Error::OutOfMemory { .. } => true,
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
}

/// Characters of user text quoted in a message before it is cut short.
const QUOTED_CHARS: usize = 60;

/// User text (a scene key, a name, a value) as a message may quote it: on one line, with
/// control characters escaped (`\n`, `\u{1b}`) and anything past `QUOTED_CHARS`
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
        let host = Error::OutOfMemory {
            what: "the image's read-back",
            file: None,
            bytes: Some(1 << 30),
            settings: &[super::Setting::Width, super::Setting::Height],
        };
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
        assert_eq!(
            host.spelled(&|s, _| format!("--{}", s.name())),
            "out of memory: the image's read-back of 1024 MiB could not be allocated: ask for \
             less through --width/--height"
        );
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
        // Settings inside an input error's message stay typed.
        let input = Error::input(
            "fod.nii",
            "lmax",
            crate::message!["3 is odd; see ", Setting::MinAmplitude.with(0.5)],
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
        // Both sides of a conflict are settings; either is spelled.
        let clash = Error::conflict(Setting::Slice, super::Relation::Exclusive, Setting::Slices);
        assert_eq!(clash.setting_of(), Some(Setting::Slice));
        assert!(clash.is_usage());
        assert_eq!(
            clash.spelled(&keyword),
            "give either slice or slices, not both"
        );
        // A limit the request sets is a usage error; one the data exceed is not.
        let limit = |settings: &'static [Setting]| Error::Limit {
            what: "image side in pixels",
            value: 20000,
            limit: 16384,
            settings,
        };
        assert!(limit(&[Setting::Width, Setting::Height]).is_usage());
        assert!(!limit(&[]).is_usage());
        assert_eq!(
            limit(&[Setting::Width, Setting::Height]).spelled(&keyword),
            "image side in pixels 20000 is over the limit of 16384: ask for less through \
             width/height"
        );
        for err in [&step, &input, &clash] {
            assert!(!err.to_string().contains("--"), "{err}");
            assert!(!err.to_string().chars().any(char::is_control), "{err}");
        }
    }

    #[test]
    fn wrapped_and_output_errors_keep_their_context() {
        use super::{Problem, Setting};
        let flag = |s: Setting, v: Option<&str>| match v {
            Some(v) => format!("--{} {v}", s.name()),
            None => format!("--{}", s.name()),
        };
        let item = Error::Item {
            what: "glyph set",
            index: 2,
            error: Box::new(Error::Unsupported {
                what: super::Asked::Ellipsoids,
                by: Setting::Offset.with(0.1),
            }),
        };
        assert_eq!(
            item.spelled(&flag),
            "glyph set 2: --offset 0.1 does not take ellipsoid glyphs, which are ray-cast in \
             closed form (not tessellated, not marched)"
        );
        assert!(!item.is_usage());
        let layout = Error::Layout {
            layout: super::LayoutName {
                order: 10,
                symmetric: true,
            },
            error: Box::new(Error::data("coefficients", Problem::Empty)),
        };
        assert!(
            layout
                .to_string()
                .contains("a symmetric tensor of order 10: coefficients: none given")
        );
        let name = Error::OutputName {
            option: "-o",
            path: "a\nb.jpg".into(),
            format: "PNG".into(),
            endings: vec![".png".into()],
        };
        assert!(name.is_usage());
        assert_eq!(
            name.to_string(),
            "-o a\\nb.jpg: writes PNG, so the name must end in .png (.jpg would mislabel the file)"
        );
        let same = Error::SameOutput {
            first: "a.png".into(),
            second: "./a.png".into(),
        };
        assert!(same.is_usage() && same.to_string().contains("a.png and ./a.png"));
        let env = Error::Environment {
            variable: "GLYPHCAST_MAX_INPUT_BYTES",
            value: "\"lots\"".into(),
            expected: "a number of bytes",
        };
        assert_eq!(
            env.to_string(),
            "GLYPHCAST_MAX_INPUT_BYTES=\"lots\": expected a number of bytes"
        );
        assert!(!env.is_usage());
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
