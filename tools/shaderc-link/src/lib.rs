//! Carries no code: its build script adds the static glslang and SPIRV-Tools libraries
//! that Debian's `libshaderc_combined.a` needs but does not contain. glyphcast's build.rs
//! names this crate with `extern crate` so those link lines reach the build-script binary.
