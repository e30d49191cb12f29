#version 450
// The lit-mesh pass: any indexed triangle mesh with per-vertex normals.

layout(set = 0, binding = 0) uniform Frame {
    mat4 view_proj;
    vec4 camera_pos;   // xyz world position
    vec4 sun_dir;      // xyz unit vector toward the sun
    vec4 sun_color;    // rgb linear radiance
    vec4 sky_color;    // rgb ambient from above
    vec4 ground_color; // rgb ambient from below
    vec4 params;       // x exposure
} frame;

layout(push_constant) uniform Object {
    mat4 model;
    vec4 albedo;   // rgb linear albedo
    vec4 material; // x shininess, y specular weight, z emission (times the albedo)
} object;

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec3 out_normal;

void main() {
    vec4 world = object.model * vec4(in_position, 1.0);
    out_world = world.xyz;
    // The model matrices sediment uses are rotation + uniform scale + translation, so
    // the upper 3x3 transforms normals correctly once renormalised.
    out_normal = mat3(object.model) * in_normal;
    gl_Position = frame.view_proj * world;
}
