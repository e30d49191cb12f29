#version 450
// Sand dust (Onoue & Nishita 3.7): each blob a camera-facing billboard, one instance of
// a four-vertex strip, carrying the blob's disc coordinates for the density falloff
// and its world position, where the fragment shader finds the sand below. The
// blob's light is worked out per corner (it changes little across one): beyond the
// paper, the grains scatter the sun's light forward (Henyey-Greenstein) and the sky's
// and sand's all round, tone mapped as the terrain is. (Expanded here rather than in
// a geometry shader, which lavapipe runs on one thread.)
#extension GL_GOOGLE_include_directive : require
#include "tonemap.glsl"

layout(push_constant) uniform Dust {
    mat4 view_proj;
    vec4 right;  // camera right, world space
    vec4 up;     // camera up, world space
} dust;

layout(set = 0, binding = 0) uniform Light {
    vec4 sun_dir;  // xyz toward the sun
    vec4 sun;      // rgb irradiance at the ground, w phase asymmetry g
    vec4 sky;      // rgb mean radiance all round, w peak opacity
    vec4 albedo;   // rgb single-scattering albedo, w fade height (m)
    vec4 eye;      // xyz eye, w dune cell size (m)
    vec4 tone;     // x exposure (the tone-mapping operator is the pipeline's), z dune grid side
} light;

layout(set = 0, binding = 3, std430) readonly buffer Blobs {
    vec4 blob[];   // two a blob: xyz centre, w radius; x its opacity (render::dust::packed)
} blobs;

layout(location = 0) out vec2 out_disc;
layout(location = 1) out vec3 out_world;
layout(location = 2) flat out vec4 out_color;  // a the blob's opacity

const float PI = 3.14159265358979323846;

float henyey_greenstein(float mu, float g) {
    float g2 = g * g;
    return (1.0 - g2) / (4.0 * PI * pow(max(1.0 + g2 - 2.0 * g * mu, 1e-6), 1.5));
}

void main() {
    vec4 blob = blobs.blob[2 * gl_InstanceIndex];
    float opacity = blobs.blob[2 * gl_InstanceIndex + 1].x;
    vec3 c = blob.xyz;
    float r = blob.w;
    vec2 corner = vec2(float(gl_VertexIndex & 1) * 2.0 - 1.0, float(gl_VertexIndex >> 1) * 2.0 - 1.0);
    vec3 p = c + (dust.right.xyz * corner.x + dust.up.xyz * corner.y) * max(r, 0.0);
    vec3 view = normalize(c - light.eye.xyz);
    float mu = dot(view, normalize(light.sun_dir.xyz));
    vec3 radiance = light.albedo.rgb
        * (light.sun.rgb * henyey_greenstein(mu, light.sun.w) + light.sky.rgb);
    out_color = vec4(tonemap(radiance, light.tone.x), opacity);
    out_disc = corner;
    out_world = p;
    // A blob of no radius collapses to a point: nothing drawn.
    gl_Position = dust.view_proj * vec4(p, 1.0);
}
