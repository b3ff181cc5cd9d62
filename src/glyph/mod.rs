//! CPU mathematics of glyphs in float64: tensors in monomial form, bounds, the exact
//! ray intersection that serves as the reference for every GPU result, the real
//! spherical harmonics (`sh`) with their map to tensors, the CPU mirror of the shaders'
//! interval and affine ranges and of the exact method's Bernstein root isolation, and
//! the tessellated glyphs of the mesh baseline.
pub mod bernstein;
pub mod bounds;
pub mod capsule;
pub mod ellipsoid;
pub(crate) mod homogeneous;
pub mod intersect;
pub mod interval;
pub mod monomials;
// Guaranteed bounds of eight convex pieces per glyph (`--proxy pieces`).
pub(crate) mod pieces;
pub mod polynomial;
pub mod proxy;
pub mod range_rounding;
pub mod real;
pub mod reference;
pub mod rotate;
pub mod sh;
pub mod shadow;
pub mod stiffness;
pub mod tensor_order;
pub mod tessellate;

/// Whether a Cartesian tensor is stored by its unique entries (Eq. 5) or in full (Eq. 4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Symmetry {
    /// The (n+1)(n+2)/2 unique entries, as monomial coefficients.
    Symmetric,
    /// All 3^n entries.
    NonSymmetric,
}

/// How negative values of f are drawn (scene format `negative`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum NegativeMode {
    /// r(u) = |f(u)|: the paper's norm.
    #[default]
    Abs,
    /// Only the part where f(u) > 0.
    Hide,
}

impl std::str::FromStr for NegativeMode {
    type Err = crate::Error;
    /// `abs` or `hide`; anything else is refused naming the `negative` setting.
    fn from_str(s: &str) -> crate::Result<Self> {
        match s {
            "abs" => Ok(NegativeMode::Abs),
            "hide" => Ok(NegativeMode::Hide),
            _ => Err(crate::Error::setting_value(
                crate::Setting::Negative,
                format!("'{}'", crate::error::quoted(s)),
                "not one of abs, hide",
            )),
        }
    }
}

impl std::fmt::Display for NegativeMode {
    /// As `negative` takes it.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            NegativeMode::Abs => "abs",
            NegativeMode::Hide => "hide",
        })
    }
}

impl NegativeMode {
    /// The shaders' code for this mode (`catalog::codes::NEGATIVE_*`), as pushed per
    /// glyph set.
    pub fn shader_code(self) -> u32 {
        match self {
            NegativeMode::Abs => crate::catalog::codes::NEGATIVE_ABS,
            NegativeMode::Hide => crate::catalog::codes::NEGATIVE_HIDE,
        }
    }
}

/// Which surface a glyph set draws of its tensors (scene format `shape`, `--glyph`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub enum GlyphShape {
    /// The polynomial glyph r(u) = |f(u)| of the paper (for DTI, the "peanut").
    #[default]
    Polynomial,
    /// The diffusion-tensor ellipsoid { D^(1/2) u } of an order-2 symmetric tensor
    /// ([`ellipsoid`]), intersected in closed form.
    Ellipsoid,
    /// The reciprocal glyph r(u) = 1/|f(u)|, implicitly |f(q)| = |q|^(n-1) (Young's
    /// modulus from the compliance quartic). f must not vanish on the sphere (so the order
    /// is even and the surface bounded); negative `abs` only; drawn by the exact method.
    Reciprocal,
    /// The glyph of a pair of forms, D of order 6 (the set's layout, symmetric) and T of
    /// order 4: r(u) = 1/λ with λ the larger root of λ² − T(u) λ + D(u) = 0, where T and
    /// D are the trace and determinant of a quadratic form restricted to the plane ⊥ u
    /// (the smallest shear modulus over that plane). Each glyph's coefficients are D's
    /// then T's (`PLANE_TRACE_COEFFICIENTS` more than the layout's); the roots must be
    /// real and positive (T > 0, D > 0); negative `abs` only; drawn by the exact method.
    PlaneMin,
    /// As [`GlyphShape::PlaneMin`], with the smaller root (the largest shear modulus).
    PlaneMax,
    /// The glyph of three forms, D of order 6 (the set's layout, symmetric), T and Q of
    /// order 4: r(u) = |λ(u) / Q(u)| with λ the smaller root of λ² − T(u) λ + D(u) = 0,
    /// drawn in sign colours by the sign of λ / Q (the smallest Poisson's ratio over the
    /// plane ⊥ u, with Q = 1/E). Each glyph's coefficients are D's, then T's, then Q's
    /// (`RATIO_EXTRA_COEFFICIENTS` more than the layout's); Q must be positive on the
    /// sphere; negative `abs` only; drawn by the exact method.
    RatioMin,
    /// As [`GlyphShape::RatioMin`], with the larger root (the largest Poisson's ratio).
    RatioMax,
}

/// The layout of a plane glyph's D (the set's layout): symmetric, order 6.
pub const PLANE_LAYOUT: TensorLayout = TensorLayout {
    order: 6,
    symmetry: Symmetry::Symmetric,
};

/// The layout of a plane glyph's T: symmetric, order 4.
pub const PLANE_TRACE_LAYOUT: TensorLayout = TensorLayout {
    order: 4,
    symmetry: Symmetry::Symmetric,
};

/// The coefficients of a plane glyph's T, after D's.
pub(crate) const PLANE_TRACE_COEFFICIENTS: usize = 15;

/// The coefficients of a ratio glyph's T and Q (both of order 4), after D's.
pub(crate) const RATIO_EXTRA_COEFFICIENTS: usize = 2 * PLANE_TRACE_COEFFICIENTS;

impl std::str::FromStr for GlyphShape {
    type Err = crate::Error;

    /// `polynomial` or `ellipsoid`; other text is an error naming the glyph setting.
    fn from_str(text: &str) -> crate::Result<Self> {
        match text {
            "polynomial" => Ok(GlyphShape::Polynomial),
            "ellipsoid" => Ok(GlyphShape::Ellipsoid),
            _ => Err(crate::Error::setting_value(
                crate::Setting::Glyph,
                format!("'{}'", crate::error::quoted(text)),
                "not one of polynomial, ellipsoid",
            )),
        }
    }
}

impl GlyphShape {
    /// The shape's name in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            GlyphShape::Polynomial => "polynomial",
            GlyphShape::Ellipsoid => "ellipsoid",
            GlyphShape::Reciprocal => "reciprocal",
            GlyphShape::PlaneMin => "plane-min",
            GlyphShape::PlaneMax => "plane-max",
            GlyphShape::RatioMin => "ratio-min",
            GlyphShape::RatioMax => "ratio-max",
        }
    }

    /// Whether the shape is a plane glyph ([`GlyphShape::PlaneMin`] or `PlaneMax`).
    pub fn is_plane(self) -> bool {
        matches!(self, GlyphShape::PlaneMin | GlyphShape::PlaneMax)
    }

    /// Whether the shape is a ratio glyph ([`GlyphShape::RatioMin`] or `RatioMax`).
    pub fn is_ratio(self) -> bool {
        matches!(self, GlyphShape::RatioMin | GlyphShape::RatioMax)
    }

    /// Whether the shape is drawn from D of order 6 and more forms of order 4: a plane or
    /// a ratio glyph.
    pub fn is_pair(self) -> bool {
        self.is_plane() || self.is_ratio()
    }

    /// The coefficients of one glyph of this shape whose tensor has `layout_count`
    /// (a plane glyph adds its T's, a ratio glyph its T's and Q's).
    pub fn coefficient_count(self, layout_count: usize) -> usize {
        if self.is_plane() {
            layout_count + PLANE_TRACE_COEFFICIENTS
        } else if self.is_ratio() {
            layout_count + RATIO_EXTRA_COEFFICIENTS
        } else {
            layout_count
        }
    }

    /// The forms of one plane or ratio glyph from its coefficients in the scene's order:
    /// D (order 6), T (order 4) and, for a ratio glyph, Q (order 4).
    pub fn pair_forms(
        self,
        coeffs: &[f64],
    ) -> crate::Result<(
        polynomial::GlyphPolynomial,
        polynomial::GlyphPolynomial,
        Option<polynomial::GlyphPolynomial>,
    )> {
        let form = polynomial::GlyphPolynomial::from_tensor;
        let (d, rest) = coeffs.split_at(PLANE_LAYOUT.coefficient_count().min(coeffs.len()));
        let (t, q) = rest.split_at(PLANE_TRACE_COEFFICIENTS.min(rest.len()));
        let denominator = if self.is_ratio() {
            Some(form(PLANE_TRACE_LAYOUT, q)?)
        } else {
            None
        };
        Ok((
            form(PLANE_LAYOUT, d)?,
            form(PLANE_TRACE_LAYOUT, t)?,
            denominator,
        ))
    }

    /// Whether the shape can be drawn with `negative`: the ellipsoid has no negative
    /// lobes to hide, and the reciprocal glyph's f has no zeros, so no lobe ends (the
    /// scene format's `shape`/`negative` and the glyph and negative settings are refused
    /// alike).
    pub fn takes(self, negative: NegativeMode) -> bool {
        self == GlyphShape::Polynomial || negative == NegativeMode::Abs
    }
}

/// A Cartesian tensor layout: order and symmetry.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TensorLayout {
    /// The tensor order n, the degree of its polynomial.
    pub order: u32,
    /// Unique entries or all of them.
    pub symmetry: Symmetry,
}

impl From<TensorLayout> for crate::error::LayoutName {
    fn from(layout: TensorLayout) -> Self {
        crate::error::LayoutName {
            order: layout.order,
            symmetric: layout.symmetry == Symmetry::Symmetric,
        }
    }
}

impl TensorLayout {
    /// Coefficients per glyph: (n+1)(n+2)/2 symmetric, 3^n non-symmetric.
    pub const fn coefficient_count(&self) -> usize {
        match self.symmetry {
            Symmetry::Symmetric => monomials::symmetric_count(self.order),
            Symmetry::NonSymmetric => monomials::nonsymmetric_count(self.order),
        }
    }
}
