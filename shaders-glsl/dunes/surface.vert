#version 450
// Dune quads: world position and the dune's own normal; the fragment shader bump maps
// the ripples onto them.

layout(set = 0, binding = 0) uniform Frame {
    mat4 view_proj;
    vec4 camera_pos;
    vec4 sun_dir;
    vec4 sun_color;
    vec4 sky_color;
    vec4 ground_color;
    vec4 params;
} frame;

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec3 out_normal;

void main() {
    out_world = in_position;
    out_normal = in_normal;
    gl_Position = frame.view_proj * vec4(in_position, 1.0);
}
