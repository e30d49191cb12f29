#version 450
// The desert's sky: each pixel's view ray looked up in the sky-view table (bilinear),
// plus the sun's disk, tone mapped like the terrain.
#extension GL_GOOGLE_include_directive : require
#include "atmosphere.glsl"
#include "tonemap.glsl"

layout(set = 0, binding = 0) uniform texture2D table;  // sky_view.comp's, rows from the nadir up
layout(set = 0, binding = 1) uniform sampler clamp_sampler;

layout(push_constant) uniform Sky {
    mat4 inverse_view_proj;
    vec4 sun;      // xyz unit direction toward the sun, w its azimuth (radians)
    vec4 camera;   // xyz eye, w exposure
    vec4 disk;     // rgb the sun disk's radiance, w cos of its angular radius
} sky;

layout(location = 0) in vec2 in_ndc;
layout(location = 0) out vec4 out_color;

void main() {
    vec4 far = sky.inverse_view_proj * vec4(in_ndc, 1.0, 1.0);
    vec3 dir = normalize(far.xyz / far.w - sky.camera.xyz);
    vec3 sun = normalize(sky.sun.xyz);
    // Bilinear between texel centres, clamped at the edges (u runs 0..pi from the
    // sun's azimuth and is mirrored beyond: clamping is the sky's own symmetry).
    vec3 hdr = texture(sampler2D(table, clamp_sampler), sky_view_uv(dir, sky.sun.w)).rgb;
    // The disk, its edge smoothed over about a pixel's worth of angle.
    float c = dot(dir, sun);
    float edge = max(fwidth(c), 1e-6);
    hdr += sky.disk.rgb * smoothstep(sky.disk.w - edge, sky.disk.w + edge, c) * step(0.0, dir.y);
    out_color = vec4(tonemap(hdr, sky.camera.w), 1.0);
}
