//! Finds the shaderc that the `shaderc-sys` crate links, as it finds it, and where that
//! is a split shared library (Debian 12's), adds the static glslang and SPIRV-Tools
//! libraries that complete it to the link; stops the build with a paragraph naming the
//! packages where no shaderc is found. See the crate's documentation (src/lib.rs).

#[path = "src/detect.rs"]
mod detect;

use std::env;
use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=src/detect.rs");
    for var in ["SHADERC_LIB_DIR", "VULKAN_SDK"] {
        println!("cargo:rerun-if-env-changed={var}");
    }
    // shaderc-sys takes an explicit folder or the SDK as they are.
    if env::var_os("SHADERC_LIB_DIR").is_some() || env::var_os("VULKAN_SDK").is_some() {
        return;
    }
    // Only Linux's system libraries are looked at (shaderc-sys's system search elsewhere
    // is macOS's SDK folder, which holds a complete shaderc).
    if env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("linux") {
        return;
    }
    let arch = env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    // pkg-config's `shaderc` first, as shaderc-sys does (the crate declares the
    // PKG_CONFIG_* variables it reads as rerun-if-env-changed).
    let dir = pkg_config::Config::new()
        .cargo_metadata(false)
        .probe("shaderc")
        .ok()
        .and_then(|library| library.link_paths.first().cloned())
        .unwrap_or_else(|| detect::system_dir(&arch));
    let dir = std::fs::canonicalize(&dir).unwrap_or(dir);
    // A newer system shaderc (complete, or split differently) reruns the check.
    for name in [
        "libshaderc.so",
        "libshaderc_shared.so",
        "libshaderc_combined.a",
    ] {
        let path: PathBuf = dir.join(name);
        if path.exists() {
            println!("cargo:rerun-if-changed={}", path.display());
        }
    }
    match detect::plan(&dir) {
        Ok(plan) => {
            for line in plan.lines(&dir) {
                println!("{line}");
            }
        }
        Err(message) => {
            eprintln!("error: {message}");
            std::process::exit(1);
        }
    }
}
