//! The render settings' flags, made from the library's table
//! ([`RENDER_SETTINGS`]): one `--KEY VALUE` per setting, its help, placeholder and
//! default the table's. The values stay text here; the library reads them
//! ([`RenderOptions::set`]), so that a bad value is refused in the same words the
//! Python module and the viewer use.
use clap::{Arg, ArgMatches, Command};
use glyphcast::Setting;
use glyphcast::render::options::{RenderOptions, Value};
use glyphcast::render::table::{Kind, RENDER_SETTINGS};

/// The render settings given on the command line, as text, in the table's order.
#[derive(Clone, Debug, Default)]
pub struct SettingFlags {
    given: Vec<(Setting, String)>,
}

impl SettingFlags {
    /// The library's render options from the flags given; a bad value is refused
    /// naming its setting (a usage error).
    pub fn options(&self) -> glyphcast::Result<RenderOptions> {
        let mut options = RenderOptions::default();
        for (setting, text) in &self.given {
            options.set(*setting, Value::Text(text))?;
        }
        Ok(options)
    }
}

impl clap::FromArgMatches for SettingFlags {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        let given = RENDER_SETTINGS
            .iter()
            .filter_map(|spec| {
                let text = matches.get_one::<String>(spec.setting.key())?;
                Some((spec.setting, text.clone()))
            })
            .collect();
        Ok(SettingFlags { given })
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(matches)?;
        Ok(())
    }
}

impl clap::Args for SettingFlags {
    fn augment_args(command: Command) -> Command {
        RENDER_SETTINGS.iter().fold(command, |command, spec| {
            let long = spec.setting.flag().trim_start_matches('-').to_owned();
            let arg = Arg::new(spec.setting.key())
                .long(long)
                .value_name(spec.value_name)
                .help(spec.help())
                // Numbers may be negative (`--light -1,0,0`).
                .allow_hyphen_values(matches!(spec.kind, Kind::Number | Kind::Numbers));
            // A switch given alone is `on` (`--shadows`).
            let arg = match spec.kind {
                Kind::Switch => arg.num_args(0..=1).default_missing_value("on"),
                _ => arg,
            };
            command.arg(arg)
        })
    }

    fn augment_args_for_update(command: Command) -> Command {
        Self::augment_args(command)
    }
}
