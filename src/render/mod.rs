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
pub(crate) mod culling_report;
pub mod frame;
pub mod glyph_data;
pub(crate) mod glyph_shadows;
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
pub mod visibility;

use crate::catalog::{GLYPH_SHAPES, GlyphShapeEntry, RAY_CAST_METHODS, RayCastMethod};
use crate::glyph::GlyphShape;
pub use crate::glyph::tessellate::MeshKind;
pub use settings::{
    AmbientOcclusion, ColorMode, Culling, Lighting, Proxy, Refinement, RenderPath, RenderSettings,
    Shadows,
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
        let index = Method::RAY_CASTING.iter().position(|&m| m == self)?;
        RAY_CAST_METHODS.get(index)
    }

    /// Whether the method marches rays through the glyph function at a fixed step (and so
    /// reads the march settings: step, refinement, centre zone).
    pub fn marches(self) -> bool {
        self.ray_cast_entry().is_some_and(|entry| entry.marches)
    }
}

/// The shader a glyph set is drawn with, besides its method's: the polynomial glyph's
/// (the method's own), or that of a glyph shape with a shader of its own (an entry of
/// [`crate::catalog`]'s glyph shapes, in that order).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ShapeShader {
    /// The polynomial glyph r = |f|, drawn by the method's shader.
    Polynomial,
    /// The DTI ellipsoid's closed form (glsl/raycast_ellipsoid.frag), whatever the
    /// method (but the impostor).
    Ellipsoid,
    /// The reciprocal glyph r = 1/|f| (glsl/raycast_exact.frag with
    /// `GLYPHCAST_RECIPROCAL`), the exact method's.
    Reciprocal,
    /// Plane glyphs, r = 1/λ with λ² − T λ + D = 0 (glsl/raycast_exact.frag with
    /// `GLYPHCAST_PLANE`), the exact method's.
    Plane,
    /// Ratio glyphs, r = |λ/Q| with λ² − T λ + D = 0 (glsl/raycast_exact.frag with
    /// `GLYPHCAST_RATIO`), the exact method's.
    Ratio,
}

impl ShapeShader {
    /// The shader that draws glyph sets of `shape`.
    pub fn of(shape: GlyphShape) -> ShapeShader {
        match shape {
            GlyphShape::Polynomial => ShapeShader::Polynomial,
            GlyphShape::Ellipsoid => ShapeShader::Ellipsoid,
            GlyphShape::Reciprocal => ShapeShader::Reciprocal,
            GlyphShape::PlaneMin | GlyphShape::PlaneMax => ShapeShader::Plane,
            GlyphShape::RatioMin | GlyphShape::RatioMax => ShapeShader::Ratio,
        }
    }

    /// What an error names when a method or path does not draw the shape; `None` for the
    /// polynomial glyph, which every method draws.
    pub(crate) fn asked(self) -> Option<crate::error::Asked> {
        use crate::error::Asked;
        match self {
            ShapeShader::Polynomial => None,
            ShapeShader::Ellipsoid => Some(Asked::Ellipsoids),
            ShapeShader::Reciprocal => Some(Asked::Reciprocal),
            ShapeShader::Plane => Some(Asked::Plane),
            ShapeShader::Ratio => Some(Asked::Ratio),
        }
    }

    /// Its entry in the catalog's glyph shapes; `None` for the polynomial glyph.
    pub(crate) fn entry(self) -> Option<&'static GlyphShapeEntry> {
        let index = match self {
            ShapeShader::Polynomial => return None,
            ShapeShader::Ellipsoid => 0,
            ShapeShader::Reciprocal => 1,
            ShapeShader::Plane => 2,
            ShapeShader::Ratio => 3,
        };
        GLYPH_SHAPES.get(index)
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Method::Fixed | Method::Interval | Method::Affine | Method::Exact => {
                let entry = self.ray_cast_entry().ok_or(std::fmt::Error)?;
                f.write_str(entry.name)
            }
            Method::Impostor => f.write_str("impostor"),
            Method::Mesh(kind) => write!(f, "{kind}"),
        }
    }
}
