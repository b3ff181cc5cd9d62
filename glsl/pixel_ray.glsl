// The pixel ray and the depth of a surface point: what every pass that shades the scene
// format's camera rays needs (the ray casters, the sphere impostor, the tessellated
// meshes). Include after frame.glsl. pixel_ray reads gl_FragCoord: a compute shader
// defines GLYPHCAST_COMPUTE and calls pixel_ray_through with its pixel.

// The ray through window position `pixel` (a pixel centre is at its index + 0.5) of the
// scene format's camera, in world space.
void pixel_ray_through(vec2 pixel, out vec3 origin, out vec3 dir) {
    vec2 s = vec2((2.0 * pixel.x * frame.viewport.x - 1.0) * frame.right.w,
                  1.0 - 2.0 * pixel.y * frame.viewport.y);
    vec3 offset = s.x * frame.right.xyz + s.y * frame.up.xyz;
    if (frame.eye.w > 0.5) {
        origin = frame.eye.xyz + offset;
        dir = frame.fwd.xyz;
    } else {
        origin = frame.eye.xyz;
        dir = normalize(frame.fwd.xyz + offset);
    }
}

#ifndef GLYPHCAST_COMPUTE
// The ray of this fragment of the scene format's camera, in world space: through the
// pixel centre, or through the sample under per-sample shading (multisampled targets).
// Window positions are taken relative to the viewport's origin.
void pixel_ray(out vec3 origin, out vec3 dir) {
    pixel_ray_through(gl_FragCoord.xy - frame.window.xy, origin, dir);
}
#endif

// The ray in a glyph's frame q = (p - centre) / rho, measured from the point of the ray
// closest to the centre (q(s) = mid + s * dir, world distance (t_mid + s) * rho), so
// that q stays well conditioned however far the camera is.
void ray_in_glyph_frame(vec3 origin, vec3 dir, vec3 centre, float rho,
                        out float t_mid, out vec3 mid) {
    vec3 o = (origin - centre) / rho;
    t_mid = -dot(o, dir);
    mid = o + t_mid * dir;
}

// Window depth of a world point: what the rasteriser would have written there.
float window_depth(vec3 world) {
    vec4 clip = frame.view_proj * vec4(world, 1.0);
    return clamp(clip.z / clip.w, 0.0, 1.0);
}
