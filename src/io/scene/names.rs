//! The format's names for its enumerated values: one table, read by `read` and written
//! by `write`, so the two cannot drift apart.
use crate::glyph::{GlyphShape, NegativeMode};

use super::ShBasis;

/// The format's name for each value of a small enum.
pub(super) trait Named: Copy + 'static {
    const ALL: &'static [Self];
    fn name(self) -> &'static str;
}

impl Named for ShBasis {
    const ALL: &'static [Self] = &[ShBasis::Tournier07, ShBasis::Descoteaux07];
    fn name(self) -> &'static str {
        ShBasis::name(self)
    }
}

impl Named for NegativeMode {
    const ALL: &'static [Self] = &[NegativeMode::Abs, NegativeMode::Hide];
    fn name(self) -> &'static str {
        match self {
            NegativeMode::Abs => "abs",
            NegativeMode::Hide => "hide",
        }
    }
}

impl Named for GlyphShape {
    const ALL: &'static [Self] = &[
        GlyphShape::Polynomial,
        GlyphShape::Ellipsoid,
        GlyphShape::Reciprocal,
        GlyphShape::PlaneMin,
        GlyphShape::PlaneMax,
        GlyphShape::RatioMin,
        GlyphShape::RatioMax,
    ];
    fn name(self) -> &'static str {
        GlyphShape::name(self)
    }
}

/// The `kind` of a glyph set before its options are read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum KindName {
    Tensor,
    Sh,
}

impl Named for KindName {
    const ALL: &'static [Self] = &[KindName::Tensor, KindName::Sh];
    fn name(self) -> &'static str {
        match self {
            KindName::Tensor => "tensor",
            KindName::Sh => "sh",
        }
    }
}

/// The camera's `projection` before its parameters are read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum ProjectionName {
    Perspective,
    Orthographic,
}

impl Named for ProjectionName {
    const ALL: &'static [Self] = &[ProjectionName::Perspective, ProjectionName::Orthographic];
    fn name(self) -> &'static str {
        match self {
            ProjectionName::Perspective => "perspective",
            ProjectionName::Orthographic => "orthographic",
        }
    }
}
