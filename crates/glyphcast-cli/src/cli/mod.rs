//! Subcommands of the `glyphcast` binary.
pub mod accuracy;
pub mod bench;
pub mod fit;
pub mod flags;
pub mod peaks;
pub mod plot;
pub mod progress;
pub mod qc;
pub mod reference;
pub mod render;
pub mod setting_flags;
pub mod stiffness;
pub mod view;
pub mod volume;
