//! Subcommands of the `glyphcast` binary.
pub mod accuracy;
pub mod render;
pub mod volume;
