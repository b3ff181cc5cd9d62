#version 450
// Robust ray casting with interval arithmetic: each segment's range of G from intervals
// of x, y and z (the natural interval extension of the generated monomial sum).
// Traversal: raycast_robust.glsl.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#define GLYPH_SEGMENT_RANGE glyph_range_interval
#include "raycast_robust.glsl"
