//! Generates the GLSL glyph functions for every tensor layout and method of the table in
//! `src/catalog.rs`, includes them into the shaders of `glsl/`, compiles everything to
//! SPIR-V with shaderc (glslang) and writes a sorted, typed table of the results to
//! `$OUT_DIR/shaders.rs`, whose entries include the SPIR-V files of `$OUT_DIR/spirv/`.
//!
//! - `build/manifest.rs` lists the variants from the table, and the fixed shaders;
//! - `build/table.rs` makes the jobs and writes the table's rows;
//! - `build/glyph_function.rs` writes each variant's f and gradient from the monomial list
//!   of `src/glyph/monomials.rs` (shared with the float64 reference);
//! - `build/range.rs` adds the interval and affine range functions of the robust methods;
//! - `build/compile.rs` compiles the jobs on every core, with a cache keyed by the
//!   preprocessed source, so that an edit recompiles only the variants it changes.

#[path = "src/glyph/monomials.rs"]
#[allow(dead_code)]
mod monomials;

#[path = "src/catalog.rs"]
#[allow(dead_code)]
mod catalog;
#[path = "build/compile.rs"]
mod compile;
// The exact method's fixed-size arithmetic, written out per variant.
#[path = "build/exact_kernels.rs"]
mod exact_kernels;
#[path = "build/glyph_function.rs"]
mod glyph_function;
#[path = "build/manifest.rs"]
mod manifest;
// The interval and affine ranges of the robust methods.
#[path = "build/range.rs"]
mod range;
#[path = "src/glyph/range_rounding.rs"]
mod range_rounding;
#[path = "build/table.rs"]
mod table;

use compile::Dirs;
// Links what completes a split system shaderc (Debian 12's) into this build script.
use glyphcast_shaderc_link as _;
// The layouts' symmetry, as the generator modules name it.
use manifest::Symmetry;
use std::path::PathBuf;

fn fail(message: String) -> ! {
    eprintln!("error: {message}");
    std::process::exit(1);
}

fn main() {
    let root = PathBuf::from(
        std::env::var("CARGO_MANIFEST_DIR").unwrap_or_else(|_| fail("CARGO_MANIFEST_DIR".into())),
    );
    let out_dir =
        PathBuf::from(std::env::var("OUT_DIR").unwrap_or_else(|_| fail("OUT_DIR".into())));
    if std::env::var("CARGO_CFG_TARGET_ENDIAN").is_ok_and(|e| e != "little") {
        fail("the SPIR-V table is written for little-endian targets".into());
    }
    let glsl_dir = root.join("glsl");
    println!("cargo:rerun-if-changed=glsl");
    println!("cargo:rerun-if-changed=build");
    println!("cargo:rerun-if-changed=src/glyph/monomials.rs");
    println!("cargo:rerun-if-changed=src/catalog.rs");
    println!("cargo:rerun-if-changed=src/glyph/range_rounding.rs");

    let (table, mut jobs) = table::shader_table();

    let dirs = Dirs {
        glsl: glsl_dir,
        generated: out_dir.join("generated"),
        cache: compile::cache_dir(&out_dir),
        spirv: out_dir.join("spirv"),
    };
    let started = std::time::Instant::now();
    let summary = compile::compile_all(&mut jobs, &dirs);
    println!(
        "shaders: {} compiled, {} from the cache, in {:.1} s",
        summary.compiled,
        summary.cached,
        started.elapsed().as_secs_f64()
    );
    let hash = format!(
        "/// A hash of every shader's source and compile options (keys the pipeline cache).\n\
         const SHADERS_HASH: u64 = {:#018x};\n",
        summary.hash
    );
    for (name, text) in [("shaders.rs", table), ("shaders_hash.rs", hash)] {
        let path = out_dir.join(name);
        if std::fs::read_to_string(&path).ok().as_deref() != Some(text.as_str())
            && let Err(e) = std::fs::write(&path, text)
        {
            fail(format!("writing {name}: {e}"));
        }
    }
}
