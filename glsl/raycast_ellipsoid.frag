#version 450
// The diffusion-tensor ellipsoid (--glyph ellipsoid, src/glyph/ellipsoid.rs): a quadric,
// intersected in closed form. Compiled for the symmetric order-2 layout only, whose
// glyph function f(q) = q^T A q then is the ellipsoid's quadric form: the CPU uploads
// A = B^2 D^-1 (eigenvalues floored), so that in the normalised frame q = (p - c) / rho,
// rho = scale * B, the surface is f(q) = 1 and the bounding sphere is |q| = 1.
//
// Along q(s) = mid + s dir (mid . dir = 0, |dir| = 1) f is the quadratic
//     f(mid) + s grad f(mid) . dir + s^2 f(dir),
// exactly (f is homogeneous of degree 2: grad f(mid) . dir = 2 mid^T A dir). Its roots
// come from the cancellation-free pair q / a and c / q. The normal is grad f = 2 A q, exact.
//
// Colour: with --color direction the whole ellipsoid takes the colour of its principal
// eigenvector (the DTI convention), which is the box axis of the longest extent: the CPU
// builds the box from the eigenvectors, longest first (GlyphSetData::boxes).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "raycast_common.glsl"

#if GLYPH_ORDER_MACRO != 2
#error "the ellipsoid shader is for order-2 tensors"
#endif

// v rotated by the unit quaternion q.
vec3 rotate_forward(vec4 q, vec3 v) {
    return v + 2.0 * cross(q.xyz, q.w * v + cross(q.xyz, v));
}

void main() {
    GlyphRay ray;
    // The ray against the bounding sphere (radius 1: no offset) and the exact box.
    if (!glyph_ray_within(1.0, ray)) {
        discard;
    }
    count_work(WORK_EVALUATIONS);
    glyph_load_inputs();
    vec3 grad_mid;
    float f_mid = glyph_f_grad(ray.mid, grad_mid);
    float a = glyph_f(ray.dir);
    float b = dot(grad_mid, ray.dir);
    float c = f_mid - 1.0;
    float disc = b * b - 4.0 * a * c;
    if (!(disc > 0.0 && a > 0.0)) {
        discard;
    }
    float q = -0.5 * (b + (b >= 0.0 ? sqrt(disc) : -sqrt(disc)));
    float r0 = q / a;
    float r1 = c / q;
    float near = min(r0, r1);
    float far = max(r0, r1);
    // The entry point; for a camera inside the ellipsoid, its exit (as the reference).
    float s_hit = near > -ray.t_mid ? near : far;
    if (!(s_hit > -ray.t_mid)) {
        discard;
    }
    vec3 p = ray.mid + s_hit * ray.dir;
    vec3 grad;
    glyph_f_grad(p, grad);
    vec3 normal = normalize(grad);

    float distance = (ray.t_mid + s_hit) * ray.rho;
    vec3 world = ray.origin + distance * ray.dir;
    float depth = window_depth(world);
    if (!shows_hit(distance, depth)) {
        discard;
    }
    gl_FragDepth = depth;

    float len = length(p);
    vec3 dir = len > 0.0 ? p / len : normal;
    if (frame.modes.z == COLOR_DIRECTION) {
        // The longest box axis: the principal eigenvector.
        vec3 e = v_box_extent;
        vec3 axis = e.x >= e.y && e.x >= e.z ? vec3(1.0, 0.0, 0.0)
                  : (e.y >= e.z ? vec3(0.0, 1.0, 0.0) : vec3(0.0, 0.0, 1.0));
        dir = rotate_forward(v_box_rotation, axis);
    }
    vec3 base = glyph_color(dir, len * ray.rho, 1.0);
    out_color = vec4(blinn_phong(base, normal, -ray.dir), 1.0);
#ifndef GLYPHCAST_NO_DISTANCE
    out_distance = distance;
#endif
}
