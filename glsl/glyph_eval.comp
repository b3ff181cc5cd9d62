#version 450
// Evaluates the generated glyph function and gradient at given points, so tests can hold
// the generated GLSL against the float64 reference.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly buffer Coefficients {
    float coeffs[];
};
layout(std430, set = 0, binding = 1) readonly buffer Points {
    vec4 points[];   // xyz: point, w: glyph index (as float)
};
layout(std430, set = 0, binding = 2) writeonly buffer Results {
    vec4 results[];  // x: f, yzw: gradient
};
layout(push_constant) uniform EvalParams {
    uint count;
} params;

#include "glyph_function.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= params.count) {
        return;
    }
    vec4 p = points[i];
    glyph_load(uint(p.w));
    vec3 grad;
    float f = glyph_f_grad(p.xyz, grad);
    results[i] = vec4(f, grad);
}
