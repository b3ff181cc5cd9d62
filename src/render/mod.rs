//! Render passes and their settings.
pub mod eval;
pub mod frame;
pub mod glyph_data;
pub mod headless;
pub mod raycast;
pub mod settings;
pub mod shaders;

pub use settings::{ColorMode, Refinement, RenderSettings};

/// Ray-glyph intersection method (`--method`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Method {
    /// The seed's fixed-step sign test with refinement.
    Fixed,
    /// The first real root of the ray polynomial, isolated by Bernstein subdivision
    /// (glsl/raycast_exact.frag); offset 0 only.
    Exact,
}

impl Method {
    /// Every method, in the order `--method` lists them.
    pub const ALL: [Method; 2] = [Method::Fixed, Method::Exact];

    /// The `--method` name.
    pub fn name(self) -> &'static str {
        match self {
            Method::Fixed => "fixed",
            Method::Exact => "exact",
        }
    }
}
