//! Makes the [`shaderc`] crate link a system shaderc that lacks glslang (Debian 12's)
//! with nothing sourced and no variable set.
//!
//! [`shaderc`]: https://docs.rs/shaderc
//!
//! `shaderc-sys` (0.10) links the system's shaderc when neither `SHADERC_LIB_DIR` nor
//! `VULKAN_SDK` is set: it looks through pkg-config, else in the system's library
//! folder. Debian 12's is split: `libshaderc.so.1` leaves about forty of glslang's and
//! SPIRV-Tools' C++ symbols undefined, none of the libraries it needs defines them, and
//! `libshaderc_combined.a` holds shaderc's own code alone, so either fails to link with
//! `undefined reference: glslang::...`. Debian's `glslang-dev` and `spirv-tools` ship
//! the missing code as static libraries.
//!
//! This crate turns on shaderc-sys's `prefer-static-linking` feature (the static
//! `libshaderc_combined.a` where the folder has one, else the shared library), and its
//! build script finds the folder shaderc-sys uses, as shaderc-sys does, and reads the
//! archive's symbol index (with the `object` crate):
//!
//! - a static shaderc that defines glslang (the Vulkan SDK's, shaderc's own build), a
//!   complete shared one, or none (shaderc-sys then builds its own from source): the
//!   build script adds nothing;
//! - a static shaderc without glslang, beside a `libshaderc.so` whose `DT_NEEDED`
//!   libraries define what it lacks (a shared glslang, as on Debian 13 and Ubuntu
//!   24.04): those shared libraries are added to the link;
//! - otherwise (Debian 12): the static `glslang`, `SPIRV`, `MachineIndependent`,
//!   `GenericCodeGen`, `OSDependent`, `OGLCompiler`, `SPIRV-Tools-opt` and
//!   `SPIRV-Tools` libraries of the same folder, and `libstdc++`; where the required
//!   ones are missing, the build stops with one paragraph naming the packages to
//!   install, instead of the linker's list of undefined symbols.
//!
//! Why static: completing Debian 12's `libshaderc.so.1` at link time (the same archives,
//! whose glslang symbols the program exports for it) links, and the program crashes in
//! the library's own `GlslangToSpv` on the first compile: the library carries glslang's
//! SPIR-V back end built against other glslang headers than `glslang-dev`'s. The static
//! archive carries no glslang code, so shaderc, glslang and SPIRV-Tools all come from the
//! system's `-dev` packages, and the program needs no `libshaderc.so.1` at run time. It
//! links with rust-lld (rustc's default) and with the system's `cc`/`ld`. Why not a
//! joined archive in `SHADERC_LIB_DIR` (what a sourced script did before): an engine,
//! an IDE or `cargo install` sources no script, and shaderc-sys does not rebuild when
//! the variable changes.
//!
//! Use: depend on this crate next to `shaderc` (a build-dependency for a build script,
//! a dependency or dev-dependency for the rest) and name it once, so that rustc links
//! it into the program:
//!
//! ```
//! use glyphcast_shaderc_link as _;
//! ```
//!
//! The crate has no items; it carries the link lines and the feature.
#![warn(missing_docs)]

#[cfg(test)]
mod detect;
