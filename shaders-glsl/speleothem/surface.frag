#version 450
// Wet calcite: normal-mapped ruggedness, lamp light, an environment-mapped sheen of a
// procedural cave (dark rock, warm lamp glow) with Schlick's Fresnel, ACES tone mapping.
#extension GL_GOOGLE_include_directive : require
#include "lighting.glsl"
#include "tonemap.glsl"

layout(set = 0, binding = 0) uniform Frame {
    mat4 view_proj;
    vec4 camera_pos;
    vec4 sun_dir;
    vec4 sun_color;
    vec4 sky_color;
    vec4 ground_color;
    vec4 params;
} frame;

layout(set = 0, binding = 2) uniform texture2D normal_map;
layout(set = 0, binding = 3) uniform sampler normal_sampler;

layout(push_constant) uniform Surface {
    vec4 params;
} surface;

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_tangent;
layout(location = 3) in vec2 in_uv;
layout(location = 4) in vec3 in_color;

layout(location = 0) out vec4 out_color;

// The cave as seen in a reflection: dark rock below and around, a warm glow toward the
// lamp, a faint cool bounce from above.
vec3 cave_environment(vec3 r, vec3 lamp_dir) {
    float up = r.y * 0.5 + 0.5;
    vec3 rock = mix(vec3(0.015, 0.012, 0.010), vec3(0.05, 0.045, 0.04), up);
    float glow = pow(max(dot(r, lamp_dir), 0.0), 24.0);
    return rock + vec3(2.2, 1.5, 0.8) * glow;
}

void main() {
    vec3 n = normalize(gl_FrontFacing ? in_normal : -in_normal);
    vec3 t = normalize(in_tangent - n * dot(in_tangent, n));
    vec3 b = cross(n, t);
    vec3 tn = texture(sampler2D(normal_map, normal_sampler), in_uv).xyz * 2.0 - 1.0;
    tn.xy *= surface.params.z;
    n = normalize(t * tn.x + b * tn.y + n * tn.z);

    vec3 v = normalize(frame.camera_pos.xyz - in_world);
    vec3 l;
    vec3 radiance;
    light_at(frame.sun_dir, frame.sun_color.rgb, in_world, l, radiance);
    vec3 albedo = in_color;
    vec3 hdr = albedo * hemisphere_ambient(n, frame.sky_color.rgb, frame.ground_color.rgb)
             + sun_light(n, v, l, albedo, radiance, 48.0, 0.35);
    // Wet film: Fresnel-weighted reflection of the cave.
    vec3 r = reflect(-v, n);
    float fresnel = 0.04 + 0.96 * pow(1.0 - max(dot(n, v), 0.0), 5.0);
    hdr += fresnel * cave_environment(r, l);
    out_color = vec4(tonemap_aces(hdr, frame.params.x), 1.0);
}
