#version 450
// Sand dust: a spherical blob whose grain density falls off from the centre; the
// light it absorbs is proportional to the density (alpha blended over the scene, as
// the paper has it). Beyond the paper: the grains scatter the sun's light forward
// (Henyey-Greenstein) and the sky's all round, tone mapped as the terrain is, and
// the blob fades out over the last metres above the sand, so the billboards meet the
// dunes without a hard line (soft particles; the terrain is a heightfield, so the
// distance to it is its height here rather than a depth-buffer read).
#extension GL_GOOGLE_include_directive : require
#include "tonemap.glsl"

layout(set = 0, binding = 0) uniform Light {
    vec4 sun_dir;  // xyz toward the sun
    vec4 sun;      // rgb irradiance at the ground, w phase asymmetry g
    vec4 sky;      // rgb mean sky radiance, w peak opacity
    vec4 albedo;   // rgb single-scattering albedo, w fade height (m)
    vec4 eye;      // xyz eye, w dune cell size (m)
    vec4 tone;     // x exposure, y operator, z dune grid side
} light;
layout(set = 0, binding = 1) uniform texture2D dune_heights;  // one period, cell units
layout(set = 0, binding = 2) uniform sampler repeat_sampler;

layout(location = 0) in vec2 in_disc;
layout(location = 1) in vec3 in_world;
layout(location = 0) out vec4 out_color;

const float PI = 3.14159265358979323846;

float henyey_greenstein(float mu, float g) {
    float g2 = g * g;
    return (1.0 - g2) / (4.0 * PI * pow(max(1.0 + g2 - 2.0 * g * mu, 1e-6), 1.5));
}

void main() {
    float r2 = dot(in_disc, in_disc);
    if (r2 > 1.0) {
        discard;
    }
    // Density through a Gaussian blob, integrated along the view ray.
    float density = exp(-4.0 * r2);
    float n = light.tone.z;
    vec2 cell = in_world.xz / light.eye.w;
    float ground = light.eye.w
        * textureLod(sampler2D(dune_heights, repeat_sampler), (cell + 0.5) / n, 0.0).r;
    float soft = smoothstep(0.0, light.albedo.w, in_world.y - ground);
    vec3 view = normalize(in_world - light.eye.xyz);
    float mu = dot(view, normalize(light.sun_dir.xyz));
    vec3 radiance = light.albedo.rgb
        * (light.sun.rgb * henyey_greenstein(mu, light.sun.w) + light.sky.rgb);
    out_color = vec4(tonemap(radiance, vec4(light.tone.xy, 0.0, 0.0)),
                     light.sky.w * density * soft);
}
