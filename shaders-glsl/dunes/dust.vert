#version 450
// Sand dust (Onoue & Nishita 3.7): one point per blob, expanded by the geometry shader.

layout(location = 0) in vec4 in_blob; // xyz centre, w radius

layout(location = 0) out vec4 out_blob;

void main() {
    out_blob = in_blob;
    gl_Position = vec4(in_blob.xyz, 1.0);
}
