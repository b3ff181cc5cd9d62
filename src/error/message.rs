//! Message text that names settings: a sequence of words and [`Setting`]s, so that each
//! front end spells the settings its way without reading them back out of a string.
//! Built with [`message!`](crate::message): `message!["give ", Setting::Mask, " or ",
//! Setting::Voxels]` reads `give --mask or --voxels` on the command line and `give mask or
//! voxels` in Python.
use super::Setting;
use std::fmt;

/// One piece of a [`Message`]: words, or a setting (with its value, if the text shows it).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Piece {
    /// Words, as they are.
    Text(String),
    /// A setting, spelled by the front end that shows the message.
    Setting(Setting, Option<String>),
}

impl From<&str> for Piece {
    fn from(text: &str) -> Self {
        Piece::Text(text.to_owned())
    }
}

impl From<String> for Piece {
    fn from(text: String) -> Self {
        Piece::Text(text)
    }
}

impl From<Setting> for Piece {
    fn from(setting: Setting) -> Self {
        Piece::Setting(setting, None)
    }
}

/// Words with the settings they name kept typed ([`Piece`]); `Display` writes the
/// settings in the library's words ([`Setting::plain`]), [`Message::spelled`] in a front
/// end's.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Message(Vec<Piece>);

impl Message {
    /// The message made of `pieces`, in order.
    pub fn from_pieces(pieces: Vec<Piece>) -> Self {
        Message(pieces)
    }

    /// The pieces, in order.
    pub fn pieces(&self) -> &[Piece] {
        &self.0
    }

    /// The settings the message names, in order.
    pub fn settings(&self) -> impl Iterator<Item = Setting> + '_ {
        self.0.iter().filter_map(|piece| match piece {
            Piece::Setting(setting, _) => Some(*setting),
            Piece::Text(_) => None,
        })
    }

    /// The text with each setting spelled by `spell(setting, value)`.
    pub fn spelled(&self, spell: &dyn Fn(Setting, Option<&str>) -> String) -> String {
        let mut out = String::new();
        for piece in &self.0 {
            match piece {
                Piece::Text(text) => out.push_str(text),
                Piece::Setting(setting, value) => out.push_str(&spell(*setting, value.as_deref())),
            }
        }
        out
    }
}

impl fmt::Display for Message {
    /// The text with settings in the library's words ([`Setting::plain`]).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.spelled(&|setting, value| setting.plain(value)))
    }
}

impl From<String> for Message {
    fn from(text: String) -> Self {
        Message(vec![Piece::Text(text)])
    }
}

impl From<&str> for Message {
    fn from(text: &str) -> Self {
        Message(vec![Piece::Text(text.to_owned())])
    }
}

impl From<&String> for Message {
    fn from(text: &String) -> Self {
        Message(vec![Piece::Text(text.clone())])
    }
}

impl From<Piece> for Message {
    fn from(piece: Piece) -> Self {
        Message(vec![piece])
    }
}

/// A [`Message`] of words and settings: each argument is text (`&str`, `String`), a
/// [`Setting`] or a setting with its value ([`Setting::with`]).
#[macro_export]
macro_rules! message {
    ($($piece:expr),* $(,)?) => {
        $crate::error::Message::from_pieces(vec![$($crate::error::Piece::from($piece)),*])
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_stay_typed_and_each_front_end_spells_them() {
        let text = crate::message![
            Setting::Method.with("exact"),
            " needs offset 0; use ",
            Setting::Method.with("fixed")
        ];
        let flag = |s: Setting, v: Option<&str>| match v {
            Some(v) => format!("--{} {v}", s.name()),
            None => format!("--{}", s.name()),
        };
        assert_eq!(
            text.spelled(&flag),
            "--method exact needs offset 0; use --method fixed"
        );
        assert_eq!(
            text.to_string(),
            "method exact needs offset 0; use method fixed"
        );
        assert_eq!(
            text.settings().collect::<Vec<_>>(),
            [Setting::Method, Setting::Method]
        );
    }
}
