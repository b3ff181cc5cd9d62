//! Render passes and their settings.
pub mod eval;
pub mod frame;
pub mod glyph_data;
pub mod headless;
pub mod range_eval;
pub mod raycast;
pub mod settings;
pub mod shaders;

pub use settings::{ColorMode, Refinement, RenderSettings};

/// Ray-glyph intersection method (`--method`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Method {
    /// The seed's fixed-step sign test with refinement.
    Fixed,
    /// Robust traversal bounded by interval arithmetic (glsl/raycast_interval.frag).
    Interval,
    /// Robust traversal bounded by reduced affine arithmetic (glsl/raycast_affine.frag).
    Affine,
}

impl Method {
    /// Every method, in the order reports list them.
    pub const ALL: [Method; 3] = [Method::Fixed, Method::Interval, Method::Affine];

    /// The name `--method` takes.
    pub fn name(self) -> &'static str {
        match self {
            Method::Fixed => "fixed",
            Method::Interval => "interval",
            Method::Affine => "affine",
        }
    }
}
