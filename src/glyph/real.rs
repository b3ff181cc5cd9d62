//! The float types the CPU mirrors of the shaders run in: f32 (what the GPU computes) and
//! f64 (the reference). One trait serves the exact method's port (`bernstein`) and the
//! interval and affine ranges (`interval`).
use std::fmt::Debug;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// f32 or f64, with the constants the ports need.
pub trait Real:
    Copy
    + PartialOrd
    + Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// 0 in this type.
    const ZERO: Self;
    /// 1 in this type.
    const ONE: Self;
    /// Unit roundoff: 2^-24 for f32, 2^-53 for f64.
    const UNIT_ROUNDOFF: f64;
    /// log2 of the smallest |q|^D that the exact method's polynomial pieces handle (the
    /// centre zone's radius is 2^(EXPONENT / D)): far enough above the type's smallest
    /// normal number for F's Bernstein coefficients, ~|q|^D times binomial weights, to
    /// stay normal.
    const ZONE_EXPONENT: f64;
    /// About two units in the last place of 1: where Newton stops.
    const RESOLUTION: f64;
    /// `v` rounded to this type.
    fn from_f64(v: f64) -> Self;
    /// The value as f64 (exact).
    fn to_f64(self) -> f64;
    /// Absolute value.
    fn abs(self) -> Self;
    /// Square root (NaN below 0).
    fn sqrt(self) -> Self;
    /// The smaller of the two.
    fn min(self, other: Self) -> Self;
    /// The larger of the two.
    fn max(self, other: Self) -> Self;
}

macro_rules! impl_real {
    ($t:ty, unit_roundoff: $u:expr, zone_exponent: $z:expr, resolution: $r:expr) => {
        impl Real for $t {
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const UNIT_ROUNDOFF: f64 = $u;
            const ZONE_EXPONENT: f64 = $z;
            const RESOLUTION: f64 = $r;
            fn from_f64(v: f64) -> Self {
                v as $t
            }
            fn to_f64(self) -> f64 {
                self as f64
            }
            fn abs(self) -> Self {
                <$t>::abs(self)
            }
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            fn min(self, other: Self) -> Self {
                <$t>::min(self, other)
            }
            fn max(self, other: Self) -> Self {
                <$t>::max(self, other)
            }
        }
    };
}
impl_real!(f32, unit_roundoff: 1.0 / 16_777_216.0, zone_exponent: -100.0, resolution: 1.2e-7);
impl_real!(f64, unit_roundoff: 1.0 / 9_007_199_254_740_992.0, zone_exponent: -1000.0, resolution: 4.5e-16);
