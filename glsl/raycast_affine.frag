#version 450
// Robust ray casting with reduced affine arithmetic: each segment's range of G from affine
// forms in the ray parameter (one noise symbol), second-order tight in the segment length.
// Traversal: raycast_robust.glsl.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#define GLYPH_SEGMENT_RANGE glyph_range_affine
#include "raycast_robust.glsl"
