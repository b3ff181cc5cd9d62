//! Render passes and their settings: the ray caster and the sphere impostor share the
//! instanced boxes of `raycast`; the tessellated baseline has its own pass in `mesh`.
//! `compute` is a second path for the exact method: a compute shader per pixel over the
//! screen tiles of `tiles`. The CPU compositing of the drawn images (box filter, colour
//! bar, labels, montage) is in `compose`; the GLSL test harnesses are in `harness`.
pub mod antialias;
pub mod batch;
pub mod component;
pub mod compose;
pub mod compute;
pub mod frame;
pub mod glyph_data;
#[doc(hidden)]
pub mod harness;
pub mod headless;
pub mod host_view;
#[cfg(test)]
mod interface;
pub mod mesh;
pub mod options;
pub mod peaks;
pub mod promote;
pub mod raycast;
pub mod settings;
pub mod shaders;
pub mod shadow_grid;
pub mod table;
pub mod tiles;
pub mod underlay;
pub mod underlay_shadows;

use crate::catalog::{
    ELLIPSOID_METHOD, PLANE_METHOD, RATIO_METHOD, RAY_CAST_METHODS, RECIPROCAL_METHOD,
    RayCastMethod,
};
pub use crate::glyph::tessellate::MeshKind;
pub use settings::{
    AmbientOcclusion, ColorMode, Lighting, Refinement, RenderPath, RenderSettings, Shadows,
};

/// How glyphs are drawn (`--method`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Method {
    /// The paper's fixed-step sign test with refinement.
    Fixed,
    /// Robust traversal bounded by interval arithmetic (glsl/raycast_interval.frag).
    Interval,
    /// Robust traversal bounded by reduced affine arithmetic (glsl/raycast_affine.frag).
    Affine,
    /// The first real root of the ray polynomial, isolated by Bernstein subdivision
    /// (glsl/raycast_exact.frag); offset 0 only.
    Exact,
    /// The closed-form intersection of the DTI ellipsoid (glsl/raycast_ellipsoid.frag):
    /// what ellipsoid glyph sets are drawn with, whatever `--method` says for the others.
    Ellipsoid,
    /// The exact method on the reciprocal glyph r = 1/|f| (glsl/raycast_exact.frag
    /// compiled with `GLYPHCAST_RECIPROCAL`): what reciprocal glyph sets are drawn with
    /// when the method is exact; the other methods refuse them.
    Reciprocal,
    /// The exact method on plane glyphs, r = 1/λ with λ² − T λ + D = 0
    /// (glsl/raycast_exact.frag compiled with `GLYPHCAST_PLANE`): what plane glyph sets
    /// are drawn with when the method is exact; the other methods refuse them.
    Plane,
    /// The exact method on ratio glyphs, r = |λ/Q| with λ² − T λ + D = 0
    /// (glsl/raycast_exact.frag compiled with `GLYPHCAST_RATIO`): what ratio glyph sets
    /// are drawn with when the method is exact; the other methods refuse them.
    Ratio,
    /// The bounding sphere of each glyph on the ray caster's boxes: the cost floor of a
    /// box-proxy ray caster, not the glyph.
    Impostor,
    /// Rasterised triangle meshes on a tessellated sphere (the FURY/DIPY/MRtrix baseline).
    Mesh(MeshKind),
}

impl Method {
    /// The methods that ray-cast the glyph function, in the order reports list them.
    pub const RAY_CASTING: [Method; 4] = [
        Method::Fixed,
        Method::Interval,
        Method::Affine,
        Method::Exact,
    ];

    /// The method's entry in the table of ray-casting methods ([`crate::catalog`]):
    /// name, shaders, what it reads. `None` for the impostor and the meshes.
    pub fn ray_cast_entry(self) -> Option<&'static RayCastMethod> {
        match self {
            Method::Ellipsoid => return Some(&ELLIPSOID_METHOD),
            Method::Reciprocal => return Some(&RECIPROCAL_METHOD),
            Method::Plane => return Some(&PLANE_METHOD),
            Method::Ratio => return Some(&RATIO_METHOD),
            _ => {}
        }
        let index = Method::RAY_CASTING.iter().position(|&m| m == self)?;
        RAY_CAST_METHODS.get(index)
    }

    /// Whether the method marches rays through the glyph function at a fixed step (and so
    /// reads the march settings: step, refinement, centre zone).
    pub fn marches(self) -> bool {
        self.ray_cast_entry().is_some_and(|entry| entry.marches)
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Method::Fixed
            | Method::Interval
            | Method::Affine
            | Method::Exact
            | Method::Ellipsoid
            | Method::Reciprocal
            | Method::Plane
            | Method::Ratio => {
                let entry = self.ray_cast_entry().ok_or(std::fmt::Error)?;
                f.write_str(entry.name)
            }
            Method::Impostor => f.write_str("impostor"),
            Method::Mesh(kind) => write!(f, "{kind}"),
        }
    }
}
