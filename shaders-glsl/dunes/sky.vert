#version 450
// A full-screen triangle; the fragment shader reconstructs each pixel's view ray.

layout(location = 0) out vec2 out_ndc;

void main() {
    vec2 p = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    out_ndc = p * 2.0 - 1.0;
    // At the far plane: drawn after the dunes, depth testing leaves only the sky.
    gl_Position = vec4(out_ndc, 1.0, 1.0);
}
