//! Completes a split system shaderc at link time, so that the [`shaderc`] crate links
//! with nothing sourced and no variable set.
//!
//! [`shaderc`]: https://docs.rs/shaderc
//!
//! `shaderc-sys` (0.10) links the system's `libshaderc.so` where it finds one (through
//! pkg-config, else the system's library folder) when neither `SHADERC_LIB_DIR` nor
//! `VULKAN_SDK` is set. Debian 12's `libshaderc.so.1` is split: it leaves about forty of
//! glslang's and SPIRV-Tools' C++ symbols undefined, and none of the libraries it needs
//! defines them, so every program linking it fails with `undefined reference:
//! glslang::...`. Debian's `glslang-dev` and `spirv-tools` ship those symbols as static
//! libraries.
//!
//! This crate's build script finds the library shaderc-sys will pick, as shaderc-sys
//! does, reads its dynamic symbol table (an ELF parse, with the `object` crate), and
//! where glslang's or SPIRV-Tools' symbols are left undefined and unresolved by its
//! `DT_NEEDED` libraries, adds the static `glslang`, `SPIRV`, `MachineIndependent`,
//! `GenericCodeGen`, `OSDependent`, `OGLCompiler`, `SPIRV-Tools-opt` and `SPIRV-Tools`
//! libraries of the same folder to the link (and `libstdc++`, which they use). The
//! linker then resolves `libshaderc.so`'s undefined symbols from them and exports the
//! definitions from the program, where `libshaderc.so` binds to them when it is loaded.
//! On a complete shaderc (Debian 13, Ubuntu 24.04, Fedora, Arch, the Vulkan SDK, or an
//! explicit `SHADERC_LIB_DIR`) it adds nothing. Where no shaderc is found, or the static
//! libraries are missing, it stops the build with one paragraph naming the packages to
//! install, instead of the linker's list of undefined symbols.
//!
//! Why not shaderc-sys's `prefer-static-linking` feature: it links
//! `libshaderc_combined.a` in place of `libshaderc.so` wherever both exist, on every
//! system (features unify across the dependency graph), and Debian's archive is just as
//! split, so it would need the same archives and would change the link on complete
//! systems too. Why not a joined archive in `SHADERC_LIB_DIR` (what a sourced script
//! did): an engine, an IDE or `cargo install` sources no script, and shaderc-sys does
//! not rebuild when the variable changes.
//!
//! Use: depend on this crate next to `shaderc` (a build-dependency for a build script,
//! a dependency or dev-dependency for the rest) and name it once, so that rustc links
//! it into the program:
//!
//! ```
//! use glyphcast_shaderc_link as _;
//! ```
//!
//! The crate has no items; it only carries the link lines.

#[cfg(test)]
mod detect;
