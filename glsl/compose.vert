#version 450
// The compute ray caster's frame drawn into rendering attachments (src/render/compute.rs
// ComposePass): one triangle that covers the viewport, made from gl_VertexIndex (no
// vertex buffer). Its depth is the fragment shader's to write.
void main() {
    vec2 corner = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    gl_Position = vec4(2.0 * corner - 1.0, 0.0, 1.0);
}
