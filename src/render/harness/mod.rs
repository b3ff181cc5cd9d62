//! Test harnesses: they run the generated GLSL at given points (`eval`) or over ray
//! segments (`range_eval`) so that the integration tests can hold it to the float64
//! code. Public for those tests only (hidden from the documentation).
pub mod eval;
pub mod range_eval;
