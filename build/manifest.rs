//! The shader variants to build, from the table of orders and methods in
//! `src/catalog.rs`: every symmetric order up to `MAX_SYMMETRIC_ORDER` and every
//! non-symmetric order up to `MAX_NONSYMMETRIC_ORDER`, each with every ray-casting
//! method, the ellipsoid's closed-form shader for the symmetric `ELLIPSOID_ORDER`, and
//! the exact method's reciprocal variant for every even order and its plane variant for
//! the symmetric `PLANE_ORDER`, and its ratio variant there too.
use crate::catalog::{
    ELLIPSOID_METHOD, ELLIPSOID_ORDER, MAX_NONSYMMETRIC_ORDER, MAX_SYMMETRIC_ORDER, PLANE_METHOD,
    PLANE_ORDER, RATIO_METHOD, RAY_CAST_METHODS, RECIPROCAL_METHOD, RayCastMethod,
    reciprocal_order,
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
    if let Some(methods) = variants.get_mut(&(Symmetry::Symmetric, ELLIPSOID_ORDER)) {
        methods.push(ELLIPSOID_METHOD);
    }
    for ((_, order), methods) in variants.iter_mut() {
        if reciprocal_order(*order) {
            methods.push(RECIPROCAL_METHOD);
        }
    }
    if let Some(methods) = variants.get_mut(&(Symmetry::Symmetric, PLANE_ORDER)) {
        methods.push(PLANE_METHOD);
        methods.push(RATIO_METHOD);
    }
    variants
}

/// The shaders that no glyph function enters, one each: (table name, file in glsl/,
/// stage, defines).
pub const FIXED_SHADERS: [(&str, &str, shaderc::ShaderKind, &[&str]); 9] = [
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
];

/// The define of the shaders that draw the underlay receiving a batch's shadows.
pub const RECEIVER_DEFINE: &str = "GLYPHCAST_RECEIVER";
