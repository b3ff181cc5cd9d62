//! Volume input for `glyphcast render` (NIfTI SH and tensor fields). Not built yet: the
//! flags exist so that the scene source has one place to grow.
use clap::Args;
use glyphcast::io::scene::Scene;
use glyphcast::{Error, Result};
use std::path::PathBuf;

/// Flags that make a scene file unnecessary.
pub const VOLUME_FLAGS: [&str; 2] = ["sh", "tensor"];

#[derive(Args)]
pub struct VolumeArgs {
    /// 4D NIfTI of SH coefficients.
    #[arg(long, value_name = "NIFTI")]
    pub sh: Option<PathBuf>,
    /// 4D NIfTI of Cartesian tensor coefficients.
    #[arg(long, value_name = "NIFTI")]
    pub tensor: Option<PathBuf>,
}

impl VolumeArgs {
    pub fn is_given(&self) -> bool {
        self.sh.is_some() || self.tensor.is_some()
    }

    pub fn scene(&self) -> Result<Scene> {
        Err(Error::Invalid("volume input is not supported yet".into()))
    }
}
