#version 450
// The sky-view table (Hillaire 2020's parameterisation) of Nishita's single scattering
// (and, as an option, Hillaire's multiple scattering),
// integrated once whenever the sun moves and looked up by every sky pixel: the "fast"
// idea of Onoue & Nishita's refs [14][15]. CPU reference: Atmosphere::sky_view in
// src/model/atmosphere.rs; tests/gpu/atmosphere.rs compares the two texel by texel.
#extension GL_GOOGLE_include_directive : require
#include "atmosphere.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, std430) buffer Table {
    vec4 radiance[];  // rgb, a 1; rows from the nadir up
} table;

// Hillaire's multiple scattering, Psi_ms by altitude (rows) and sun cosine (columns):
// MultipleScattering in src/model/atmosphere.rs, made there once per atmosphere. An
// RGBA32F texel buffer (MS_SIZE^2 texels, within every device's limit): llvmpipe
// gathers a texel fetch for its 8 lanes at once but reads a storage buffer lane by
// lane, and each view sample reads four.
layout(set = 0, binding = 1) uniform samplerBuffer multiple_psi;

vec3 psi_at(uint i, uint j) {
    return texelFetch(multiple_psi, int(j * MS_SIZE + i)).rgb;
}

// The same table for the sky to sample (bilinear, half floats).
layout(set = 0, binding = 2, rgba16f) uniform writeonly image2D table_image;

layout(push_constant) uniform Params {
    Air air;
    vec4 view;     // x viewer radius, y sin and z cos of the sun's elevation
    vec4 ambient;  // rgb the sky's irradiance on the ground (units of the sun's)
    uvec4 size;    // x width (azimuths 0..pi from the sun's), y height (elevations),
                   // z multiple scattering on (1)
} pc;

// MultipleScattering::at: bilinear between texel centres, clamped.
vec3 multiple_at(Air a, float h, float mu_s) {
    float n = float(MS_SIZE);
    float top = a.sun.w - a.ground.w;
    float x = clamp((mu_s + 1.0) * 0.5 * n - 0.5, 0.0, n - 1.0);
    float y = clamp(h / top * n - 0.5, 0.0, n - 1.0);
    uint i = uint(floor(x));
    uint j = uint(floor(y));
    uint i1 = min(i + 1u, MS_SIZE - 1u);
    uint j1 = min(j + 1u, MS_SIZE - 1u);
    float fx = x - float(i);
    float fy = y - float(j);
    vec3 p = mix(psi_at(i, j), psi_at(i1, j), fx);
    vec3 q = mix(psi_at(i, j1), psi_at(i1, j1), fx);
    return mix(p, q, fy);
}

void main() {
    uvec2 id = gl_GlobalInvocationID.xy;
    if (id.x >= pc.size.x || id.y >= pc.size.y) {
        return;
    }
    // Field by field: copying the push-constant struct whole is an OpCopyLogical,
    // which naga does not read.
    Air a = Air(pc.air.rayleigh, pc.air.mie, pc.air.ground, pc.air.sun, pc.air.ozone);
    float u = (float(id.x) + 0.5) / float(pc.size.x);
    float v = (float(id.y) + 0.5) / float(pc.size.y);
    float e = elevation_of_v(v);
    float az = u * PI;
    vec3 view = vec3(cos(e) * cos(az), sin(e), cos(e) * sin(az));
    vec3 sun = vec3(pc.view.z, pc.view.y, 0.0);

    float r = pc.view.x;
    float mu = view.y;
    float mu_s = sun.y;
    float nu = dot(view, sun);
    float ground = distance_to_ground(a, r, mu);
    float far = ground >= 0.0 ? ground : distance_to_top(a, r, mu);
    vec3 depth = vec3(0.0);
    vec3 sum = vec3(0.0);
    for (uint i = 0u; i < VIEW_SAMPLES; ++i) {
        vec2 s = ray_sample(i, VIEW_SAMPLES, far);
        float rt = radius_at(r, mu, s.x);
        float ht = rt - a.ground.w;
        vec3 ext = air_extinction(a, ht);
        vec3 to_sample = depth + ext * (0.5 * s.y);
        float mu_st = (r * mu_s + s.x * nu) / rt;
        vec3 source = transmittance_to_space(a, rt, mu_st) * air_scattering(a, ht, nu);
        if (pc.size.z != 0u) {
            source += multiple_at(a, ht, mu_st) * air_total_scattering(a, ht);
        }
        sum += exp(-to_sample) * source * s.y;
        depth += ext * s.y;
    }
    if (ground >= 0.0) {
        float rg = a.ground.w;
        float mu_g = clamp((r * mu_s + far * nu) / rg, -1.0, 1.0);
        vec3 lit = transmittance_to_space(a, rg, mu_g) * max(mu_g, 0.0) + pc.ambient.rgb;
        sum += exp(-depth) * lit * a.ground.rgb / PI;
    }
    vec4 radiance = vec4(sum * a.sun.rgb, 1.0);
    table.radiance[id.y * pc.size.x + id.x] = radiance;
    imageStore(table_image, ivec2(id), radiance);
}
