//! `glyphcast reference DIR`: the command line's reference made from its own definition
//! (clap's): a Markdown page per command (`cli/*.md`), man pages (`man/*.1`, by
//! clap_mangen) and shell completions (`completions/`, by clap_complete) for bash, zsh and
//! fish. `tools/gen-docs.sh` writes them into `docs/reference/`; a test fails when what
//! is committed there differs from what this makes.
use clap::{Arg, ArgAction, Command};
use glyphcast::{Error, Result};
use std::path::Path;

/// Every file of the reference, by its path under the output folder, with its bytes.
pub fn files(command: &Command) -> Result<Vec<(String, Vec<u8>)>> {
    let mut command = command.clone();
    command.build();
    let mut out = Vec::new();
    let mut index = String::from(
        "# Command-line reference\n\nGenerated from the command line's definition by \
         `bash tools/gen-docs.sh`; every command's `--help` says the same.\n\n\
         | command | what it does |\n|---|---|\n",
    );
    for sub in visible_subcommands(&command) {
        let name = sub.get_name();
        index.push_str(&format!(
            "| [`glyphcast {name}`]({name}.md) | {} |\n",
            one_line(sub.get_about().map(|a| a.to_string()).unwrap_or_default())
        ));
        out.push((format!("cli/{name}.md"), page(sub).into_bytes()));
        out.push((
            format!("man/glyphcast-{name}.1"),
            man(sub, &format!("glyphcast-{name}"))?,
        ));
    }
    out.insert(0, ("cli/index.md".into(), index.into_bytes()));
    out.push(("man/glyphcast.1".into(), man(&command, "glyphcast")?));
    for (shell, file) in [
        (clap_complete::Shell::Bash, "glyphcast.bash"),
        (clap_complete::Shell::Zsh, "_glyphcast"),
        (clap_complete::Shell::Fish, "glyphcast.fish"),
    ] {
        let mut bytes = Vec::new();
        clap_complete::generate(shell, &mut command.clone(), "glyphcast", &mut bytes);
        out.push((format!("completions/{file}"), bytes));
    }
    Ok(out)
}

/// Writes [`files`] under `dir` (made if missing).
pub fn write(command: &Command, dir: &Path) -> Result<()> {
    for (path, bytes) in files(command)? {
        let path = dir.join(path);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))?;
        }
        glyphcast::io::atomic::write_atomic(&path, &bytes)?;
    }
    Ok(())
}

fn visible_subcommands(command: &Command) -> impl Iterator<Item = &Command> {
    // clap's own `help` subcommand is no command of glyphcast's.
    command
        .get_subcommands()
        .filter(|s| !s.is_hide_set() && s.get_name() != "help")
}

fn one_line(text: String) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

fn man(command: &Command, name: &str) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    let command = command.clone().name(name.to_owned());
    clap_mangen::Man::new(command)
        .render(&mut bytes)
        .map_err(|e| Error::io(Path::new(name), e))?;
    Ok(bytes)
}

/// One command's page: what it does, its usage, then each argument with its value, its
/// default and its help.
fn page(command: &Command) -> String {
    let name = command.get_name();
    let mut out = format!("# glyphcast {name}\n\n");
    if let Some(about) = command.get_long_about().or(command.get_about()) {
        out.push_str(&format!("{}\n\n", one_line(about.to_string())));
    }
    let usage = command
        .clone()
        .bin_name(format!("glyphcast {name}"))
        .render_usage()
        .to_string();
    out.push_str(&format!(
        "```text\n{}\n```\n\n",
        usage.trim_start_matches("Usage: ")
    ));
    let arguments: Vec<&Arg> = command
        .get_arguments()
        .filter(|a| !a.is_hide_set() && a.get_id() != "help" && a.get_id() != "version")
        .collect();
    let (positional, options): (Vec<&Arg>, Vec<&Arg>) =
        arguments.into_iter().partition(|a| a.is_positional());
    for (title, args) in [("Arguments", positional), ("Options", options)] {
        if args.is_empty() {
            continue;
        }
        out.push_str(&format!("## {title}\n\n"));
        for arg in args {
            out.push_str(&format!("- `{}`", spelling(arg)));
            if let Some(help) = arg.get_long_help().or(arg.get_help()) {
                out.push_str(&format!(": {}", one_line(help.to_string())));
            }
            let defaults: Vec<String> = arg
                .get_default_values()
                .iter()
                .map(|v| v.to_string_lossy().into_owned())
                .collect();
            if !defaults.is_empty() && takes_value(arg) {
                out.push_str(&format!(" (default: `{}`)", defaults.join(",")));
            }
            out.push('\n');
        }
        out.push('\n');
    }
    if let Some(after) = command.get_after_help() {
        out.push_str(&format!("{}\n", one_line(after.to_string())));
    }
    out
}

fn takes_value(arg: &Arg) -> bool {
    matches!(arg.get_action(), ArgAction::Set | ArgAction::Append)
}

fn spelling(arg: &Arg) -> String {
    let value = arg
        .get_value_names()
        .map(|names| {
            names
                .iter()
                .map(|n| format!("<{n}>"))
                .collect::<Vec<_>>()
                .join(" ")
        })
        .unwrap_or_else(|| format!("<{}>", arg.get_id().as_str().to_uppercase()));
    if arg.is_positional() {
        return value;
    }
    let mut flag = match (arg.get_short(), arg.get_long()) {
        (Some(s), Some(l)) => format!("-{s}, --{l}"),
        (None, Some(l)) => format!("--{l}"),
        (Some(s), None) => format!("-{s}"),
        (None, None) => String::new(),
    };
    if takes_value(arg) {
        flag.push(' ');
        flag.push_str(&value);
    }
    flag
}
