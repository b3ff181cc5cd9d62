//! The one error type of the crate: every refusal names the entry or field at fault.

use std::fmt;

/// Why an input was refused.
///
/// Matrix rows and columns are 1-based, as in the Voigt names `C11`…`C66`.
#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// A stiffness entry is NaN or infinite.
    NonFinite {
        /// Row of the entry (1-based).
        row: usize,
        /// Column of the entry (1-based).
        column: usize,
    },
    /// `C[row][column]` and `C[column][row]` differ by more than `1e-6 · max|C|`.
    NotSymmetric {
        /// Row of the upper entry (1-based).
        row: usize,
        /// Column of the upper entry (1-based).
        column: usize,
        /// The value at (`row`, `column`).
        upper: f64,
        /// The value at (`column`, `row`).
        lower: f64,
    },
    /// The stiffness matrix is not positive definite: the crystal would be
    /// mechanically unstable (pass `allow_unstable` to compute anyway).
    Unstable {
        /// The smallest eigenvalue of the 6x6 Voigt stiffness matrix.
        smallest_eigenvalue: f64,
    },
    /// The stiffness matrix is singular (even with `allow_unstable`): it has no compliance.
    Singular {
        /// The eigenvalue of smallest magnitude of the 6x6 Voigt stiffness matrix.
        smallest_eigenvalue: f64,
    },
    /// A direction was the zero vector or had a NaN or infinite component.
    BadDirection {
        /// Which argument: `"u"` or `"v"`.
        argument: &'static str,
    },
    /// The second direction of a shear modulus or Poisson's ratio is not
    /// perpendicular to the first (|u·v| > 1e-6 after normalisation).
    NotPerpendicular {
        /// The cosine of the angle between the normalised `u` and `v`.
        cosine: f64,
    },
    /// A Bunge Euler angle is NaN or infinite.
    NonFiniteAngle {
        /// `"phi1"`, `"Phi"` or `"phi2"`.
        angle: &'static str,
    },
    /// A 3x3 matrix given as a rotation is not one.
    NotRotation(RotationDefect),
}

/// What is wrong with a matrix given as a rotation (tolerance 1e-6).
#[derive(Debug, Clone, PartialEq)]
pub enum RotationDefect {
    /// An entry is NaN or infinite.
    NonFinite {
        /// Row of the entry (1-based).
        row: usize,
        /// Column of the entry (1-based).
        column: usize,
    },
    /// Entry (`row`, `column`) of `g gᵀ` differs from the identity's by `deviation`.
    NotOrthonormal {
        /// Row of the entry of `g gᵀ` (1-based).
        row: usize,
        /// Column of the entry of `g gᵀ` (1-based).
        column: usize,
        /// `(g gᵀ - I)[row][column]`.
        deviation: f64,
    },
    /// Orthonormal but a reflection: the determinant is not +1.
    NotProper {
        /// The determinant of the matrix.
        determinant: f64,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::NonFinite { row, column } => {
                write!(f, "stiffness entry C{row}{column} is not a finite number")
            }
            Error::NotSymmetric {
                row,
                column,
                upper,
                lower,
            } => write!(
                f,
                "stiffness matrix is not symmetric: C{row}{column} = {upper} but \
                 C{column}{row} = {lower}"
            ),
            Error::Unstable {
                smallest_eigenvalue,
            } => write!(
                f,
                "stiffness matrix is not positive definite (smallest eigenvalue \
                 {smallest_eigenvalue}): the crystal is mechanically unstable"
            ),
            Error::Singular {
                smallest_eigenvalue,
            } => write!(
                f,
                "stiffness matrix is singular (eigenvalue {smallest_eigenvalue}): \
                 it has no compliance"
            ),
            Error::BadDirection { argument } => {
                write!(f, "direction {argument} is zero or not finite")
            }
            Error::NotPerpendicular { cosine } => write!(
                f,
                "directions u and v are not perpendicular (cos = {cosine})"
            ),
            Error::NonFiniteAngle { angle } => {
                write!(f, "Euler angle {angle} is not a finite number")
            }
            Error::NotRotation(defect) => write!(f, "not a rotation matrix: {defect}"),
        }
    }
}

impl fmt::Display for RotationDefect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RotationDefect::NonFinite { row, column } => {
                write!(f, "entry ({row}, {column}) is not a finite number")
            }
            RotationDefect::NotOrthonormal {
                row,
                column,
                deviation,
            } => write!(
                f,
                "not orthonormal: entry ({row}, {column}) of g gᵀ is off the identity's \
                 by {deviation}"
            ),
            RotationDefect::NotProper { determinant } => {
                write!(f, "determinant {determinant} instead of +1 (a reflection)")
            }
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::NotRotation(defect) => Some(defect),
            _ => None,
        }
    }
}

impl std::error::Error for RotationDefect {}

impl From<RotationDefect> for Error {
    fn from(defect: RotationDefect) -> Self {
        Error::NotRotation(defect)
    }
}
