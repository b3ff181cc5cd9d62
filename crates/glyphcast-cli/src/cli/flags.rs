//! The command line's words for the library's settings: each [`Setting`] is spelled as
//! its flag (`--magnitude-range`), with its value after it (`--step 0.0001`), in every
//! message the library's errors carry ([`Error::spelled`]). The library itself names no
//! flag.
use glyphcast::{Error, Setting};

/// The flag of `setting`: its key with `-` for `_` (`--magnitude-range`).
pub fn flag(setting: Setting) -> String {
    setting.flag()
}

/// `setting` as the command line writes it, with `value` if any.
pub fn spell(setting: Setting, value: Option<&str>) -> String {
    match value {
        Some(value) => format!("{} {value}", flag(setting)),
        None => flag(setting),
    }
}

/// The one-line message of `err` in the command line's words.
pub fn message(err: &Error) -> String {
    err.spelled(&spell)
}

/// The exit code of `err`: 2 for a command line that asks for something impossible (a
/// refused setting, options that clash), 1 for bad data or a failure of the machine.
pub fn exit_code(err: &Error) -> i32 {
    match err {
        err if err.is_usage() => 2,
        _ => 1,
    }
}
