#version 450
// Transform-feedback self-test: pass each vertex (xyz position, w id) to the geometry
// stage unchanged.

layout(location = 0) in vec4 in_vertex;
layout(location = 0) out vec4 out_vertex;

void main() {
    out_vertex = in_vertex;
    gl_Position = vec4(in_vertex.xyz, 1.0);
}
