//! Subcommands of the `glyphcast` binary.
pub mod accuracy;
pub mod bench;
pub mod progress;
pub mod render;
pub mod volume;
