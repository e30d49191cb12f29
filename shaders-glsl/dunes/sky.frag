#version 450
#extension GL_GOOGLE_include_directive : require
#include "sky.glsl"
#include "tonemap.glsl"

layout(push_constant) uniform Sky {
    mat4 inverse_view_proj;
    vec4 sun;       // xyz unit direction toward the sun
    vec4 camera;    // xyz eye, w exposure
} sky;

layout(location = 0) in vec2 in_ndc;
layout(location = 0) out vec4 out_color;

void main() {
    vec4 far = sky.inverse_view_proj * vec4(in_ndc, 1.0, 1.0);
    vec3 dir = normalize(far.xyz / far.w - sky.camera.xyz);
    out_color = vec4(tonemap_aces(sky_radiance(dir, normalize(sky.sun.xyz)), sky.camera.w), 1.0);
}
