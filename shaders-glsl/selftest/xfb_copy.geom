#version 450
// Transform-feedback self-test: re-emit every triangle, moved by `offset` and with
// each vertex ID incremented by 2 (the shape of Tortelli & Walter's ring pass, without
// the new ring), captured on stream 0.

layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

layout(push_constant) uniform Step {
    vec4 offset; // xyz added to every position
} step;

layout(location = 0) in vec4 in_vertex[];
layout(location = 0, xfb_buffer = 0, xfb_offset = 0, xfb_stride = 16) out vec4 captured;

void main() {
    for (int i = 0; i < 3; ++i) {
        captured = vec4(in_vertex[i].xyz + step.offset.xyz, in_vertex[i].w + 2.0);
        gl_Position = vec4(captured.xyz, 1.0);
        EmitVertex();
    }
    EndPrimitive();
}
