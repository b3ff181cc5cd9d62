//! Subcommands of the `glyphcast` binary.
pub mod render;
pub mod volume;
