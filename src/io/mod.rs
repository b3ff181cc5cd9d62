//! Files in and out: scene JSON, PNG images and NumPy depth maps.
pub mod atomic;
pub mod npy;
pub mod png;
pub mod scene;
