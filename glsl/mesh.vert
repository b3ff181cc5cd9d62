#version 450
// Tessellated glyphs (src/render/mesh.rs): one instanced, indexed draw per glyph set.
// The index buffer is the unit sphere's triangulation, shared by every glyph; each
// instance pulls its own vertices (offset from the centre and normal, world units) from a
// storage buffer, glyph-major, and its centre from the same 16-byte instance the ray
// caster uses.
#extension GL_GOOGLE_include_directive : require
#include "frame.glsl"

layout(std430, set = 0, binding = 2) readonly buffer MeshVertices {
    float mesh_vertices[];   // per vertex: offset xyz, normal xyz
};

// Vertices per glyph: a property of the triangulation, so one pipeline per mesh kind.
layout(constant_id = 0) const uint VERTICES_PER_GLYPH = 1u;

layout(location = 0) in vec4 center_radius;

layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_offset;
layout(location = 2) out vec3 v_normal;

void main() {
    uint base = 6u * (uint(gl_InstanceIndex) * VERTICES_PER_GLYPH + uint(gl_VertexIndex));
    vec3 offset = vec3(mesh_vertices[base], mesh_vertices[base + 1u], mesh_vertices[base + 2u]);
    v_normal = vec3(mesh_vertices[base + 3u], mesh_vertices[base + 4u], mesh_vertices[base + 5u]);
    v_offset = offset;
    v_world = center_radius.xyz + offset;
    gl_Position = frame.view_proj * vec4(v_world, 1.0);
}
