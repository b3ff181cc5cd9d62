//! The shader variants to build, from the table of orders, methods and glyph shapes in
//! `src/catalog.rs`: every symmetric order up to `MAX_SYMMETRIC_ORDER` and every
//! non-symmetric order up to `MAX_NONSYMMETRIC_ORDER`, each with every ray-casting
//! method, and each glyph shape's shader (`GLYPH_SHAPES`) for the layouts it lists.
use crate::catalog::{
    GLYPH_SHAPES, MAX_NONSYMMETRIC_ORDER, MAX_SYMMETRIC_ORDER, RAY_CAST_METHODS, RayCastMethod,
};
use std::collections::BTreeMap;

#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Symmetry {
    Symmetric,
    NonSymmetric,
}

/// Per tensor layout (symmetry, order), sorted so that the table and the build are
/// reproducible: the methods to compile.
pub fn variants() -> BTreeMap<(Symmetry, u32), Vec<RayCastMethod>> {
    let families = [
        (Symmetry::Symmetric, MAX_SYMMETRIC_ORDER),
        (Symmetry::NonSymmetric, MAX_NONSYMMETRIC_ORDER),
    ];
    let mut variants: BTreeMap<_, _> = families
        .into_iter()
        .flat_map(|(symmetry, max)| {
            (1..=max).map(move |order| ((symmetry, order), RAY_CAST_METHODS.to_vec()))
        })
        .collect();
    // Each glyph shape with a shader of its own, where the catalog compiles it.
    for ((symmetry, order), methods) in variants.iter_mut() {
        let symmetric = *symmetry == Symmetry::Symmetric;
        for shape in GLYPH_SHAPES {
            if shape.compiled_for(symmetric, *order) {
                methods.push(shape.shader);
            }
        }
    }
    variants
}

/// The shaders that no glyph function enters, one each: (table name, file in glsl/,
/// stage, defines).
pub const FIXED_SHADERS: [(&str, &str, shaderc::ShaderKind, &[&str]); 14] = [
    (
        "RAYCAST_VERTEX",
        "raycast.vert",
        shaderc::ShaderKind::Vertex,
        &[],
    ),
    (
        "IMPOSTOR_FRAGMENT",
        "impostor.frag",
        shaderc::ShaderKind::Fragment,
        &[],
    ),
    ("MESH_VERTEX", "mesh.vert", shaderc::ShaderKind::Vertex, &[]),
    (
        "MESH_FRAGMENT",
        "mesh.frag",
        shaderc::ShaderKind::Fragment,
        &[],
    ),
    (
        "UNDERLAY_VERTEX",
        "underlay.vert",
        shaderc::ShaderKind::Vertex,
        &[],
    ),
    (
        "UNDERLAY_FRAGMENT",
        "underlay.frag",
        shaderc::ShaderKind::Fragment,
        &[],
    ),
    // The underlay's planes drawn again to receive a batch's shadows (the exact
    // method's receiver fragment shader, src/render/underlay_shadows.rs).
    (
        "UNDERLAY_RECEIVER_VERTEX",
        "underlay.vert",
        shaderc::ShaderKind::Vertex,
        &[RECEIVER_DEFINE],
    ),
    (
        "PEAKS_VERTEX",
        "peaks.vert",
        shaderc::ShaderKind::Vertex,
        &[],
    ),
    (
        "PEAKS_FRAGMENT",
        "peaks.frag",
        shaderc::ShaderKind::Fragment,
        &[],
    ),
    // Streamlines drawn as lines: the peaks' quad as a flat ribbon (src/render/peaks.rs).
    (
        "LINES_VERTEX",
        "peaks.vert",
        shaderc::ShaderKind::Vertex,
        &[LINES_DEFINE],
    ),
    (
        "LINES_FRAGMENT",
        "lines.frag",
        shaderc::ShaderKind::Fragment,
        &[],
    ),
    // The compute ray caster's frame drawn into rendering attachments
    // (src/render/compute.rs ComposePass), with and without the distance output.
    (
        "COMPOSE_VERTEX",
        "compose.vert",
        shaderc::ShaderKind::Vertex,
        &[],
    ),
    (
        "COMPOSE_FRAGMENT",
        "compose.frag",
        shaderc::ShaderKind::Fragment,
        &[],
    ),
    (
        "COMPOSE_COLOR_ONLY_FRAGMENT",
        "compose.frag",
        shaderc::ShaderKind::Fragment,
        &[NO_DISTANCE_DEFINE],
    ),
];

/// Defined when a fragment shader is compiled for a colour attachment only: the shader
/// then leaves out its `out_distance` output (location 1).
pub const NO_DISTANCE_DEFINE: &str = "GLYPHCAST_NO_DISTANCE";

/// The define of glsl/peaks.vert's build that draws streamlines as lines.
pub const LINES_DEFINE: &str = "GLYPHCAST_LINES";

/// The define of the shaders that draw the underlay receiving a batch's shadows.
pub const RECEIVER_DEFINE: &str = "GLYPHCAST_RECEIVER";
