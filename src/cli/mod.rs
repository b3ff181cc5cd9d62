//! Subcommands of the `glyphcast` binary.
pub mod fit;
pub mod render;
pub mod stiffness;
pub mod volume;
