//! Debian packages shaderc (libshaderc-dev) without glslang inside its static archive.
//! When that archive and the glslang/SPIRV-Tools static libraries are present, shaderc-sys
//! links `shaderc_combined` statically (feature `prefer-static-linking`) and we add the
//! rest here. When they are absent, shaderc-sys builds shaderc from source, whose archive
//! already contains glslang, and this script adds nothing.
use std::path::{Path, PathBuf};

const GLSLANG_LIBS: [&str; 8] = [
    "glslang",
    "SPIRV",
    "MachineIndependent",
    "GenericCodeGen",
    "OSDependent",
    "OGLCompiler",
    "SPIRV-Tools-opt",
    "SPIRV-Tools",
];

fn system_lib_dir() -> Option<PathBuf> {
    if let Ok(dir) = std::env::var("SHADERC_LIB_DIR") {
        return Some(PathBuf::from(dir));
    }
    let arch = std::env::var("CARGO_CFG_TARGET_ARCH").ok()?;
    let dir = PathBuf::from(format!("/usr/lib/{arch}-linux-gnu"));
    dir.is_dir().then_some(dir)
}

fn has_static(dir: &Path, name: &str) -> bool {
    dir.join(format!("lib{name}.a")).is_file()
}

fn main() {
    println!("cargo:rerun-if-env-changed=SHADERC_LIB_DIR");
    let Some(dir) = system_lib_dir() else { return };
    let complete = has_static(&dir, "shaderc_combined")
        && GLSLANG_LIBS.iter().all(|lib| has_static(&dir, lib));
    if !complete {
        println!(
            "cargo:warning=system shaderc/glslang static libraries not found in {}; \
             shaderc-sys will build from source (slow)",
            dir.display()
        );
        return;
    }
    println!("cargo:rustc-link-search=native={}", dir.display());
    // shaderc_combined is named again here, first, so that the static archives resolve
    // left to right whatever order the linker sees the two crates in.
    println!("cargo:rustc-link-lib=static=shaderc_combined");
    for lib in GLSLANG_LIBS {
        println!("cargo:rustc-link-lib=static={lib}");
    }
    println!("cargo:rustc-link-lib=dylib=stdc++");
}
