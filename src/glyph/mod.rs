//! CPU mathematics of glyphs in float64: tensors in monomial form, bounds and the exact
//! ray intersection that serves as the reference for every GPU result.
pub mod bernstein;
pub mod bounds;
pub mod intersect;
pub mod monomials;
pub mod polynomial;
pub mod reference;

/// Whether a Cartesian tensor is stored by its unique entries (Eq. 5) or in full (Eq. 4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Symmetry {
    Symmetric,
    NonSymmetric,
}

/// How negative values of f are drawn (scene format `negative`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum NegativeMode {
    /// r(u) = |f(u)|: the seed's norm.
    #[default]
    Abs,
    /// Only the part where f(u) > 0.
    Hide,
}

/// A Cartesian tensor layout: order and symmetry.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TensorLayout {
    pub order: u32,
    pub symmetry: Symmetry,
}

impl TensorLayout {
    pub const fn coefficient_count(&self) -> usize {
        match self.symmetry {
            Symmetry::Symmetric => monomials::symmetric_count(self.order),
            Symmetry::NonSymmetric => monomials::nonsymmetric_count(self.order),
        }
    }
}
