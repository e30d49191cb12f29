#version 450
// Sand dust: each blob becomes a camera-facing billboard (two triangles) carrying the
// blob's disc coordinates for the density falloff and its world position, where the
// fragment shader finds the sand below. The blob's light is worked out here, once per
// blob (it changes little across one): beyond the paper, the grains scatter the sun's
// light forward (Henyey-Greenstein) and the sky's and sand's all round, tone mapped as
// the terrain is.
#extension GL_GOOGLE_include_directive : require
#include "tonemap.glsl"

layout(points) in;
layout(triangle_strip, max_vertices = 4) out;

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
    vec4 tone;     // x exposure, y operator, z dune grid side
} light;

layout(location = 0) in vec4 in_blob[];
layout(location = 0) out vec2 out_disc;
layout(location = 1) out vec3 out_world;
layout(location = 2) flat out vec3 out_color;

const float PI = 3.14159265358979323846;

float henyey_greenstein(float mu, float g) {
    float g2 = g * g;
    return (1.0 - g2) / (4.0 * PI * pow(max(1.0 + g2 - 2.0 * g * mu, 1e-6), 1.5));
}

void main() {
    vec3 c = in_blob[0].xyz;
    float r = in_blob[0].w;
    if (r <= 0.0) {
        return;
    }
    vec3 view = normalize(c - light.eye.xyz);
    float mu = dot(view, normalize(light.sun_dir.xyz));
    vec3 radiance = light.albedo.rgb
        * (light.sun.rgb * henyey_greenstein(mu, light.sun.w) + light.sky.rgb);
    vec3 color = tonemap(radiance, vec4(light.tone.xy, 0.0, 0.0));
    for (int i = 0; i < 4; ++i) {
        vec2 corner = vec2(float(i & 1) * 2.0 - 1.0, float(i >> 1) * 2.0 - 1.0);
        vec3 p = c + (dust.right.xyz * corner.x + dust.up.xyz * corner.y) * r;
        out_disc = corner;
        out_world = p;
        out_color = color;
        gl_Position = dust.view_proj * vec4(p, 1.0);
        EmitVertex();
    }
    EndPrimitive();
}
