// The lit-mesh pass's shading: the body of `lit_mesh.frag` and of
// `lit_mesh_shadowed.frag` (the lamp's light through its shadow map, set 1).
#include "lighting.glsl"
#include "tonemap.glsl"
#include "noise.glsl"
#ifdef SHADOWED
#include "shadow.glsl"
#endif

layout(set = 0, binding = 0) uniform Frame {
    mat4 view_proj;
    vec4 camera_pos;
    vec4 sun_dir;
    vec4 sun_color;
    vec4 sky_color;
    vec4 ground_color;
    vec4 params;
} frame;

layout(push_constant) uniform Object {
    mat4 model;
    vec4 albedo;
    vec4 material; // x shininess, y specular weight, z emission, w > 0.5: rock texture
} object;

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;

layout(location = 0) out vec4 out_color;

// Rock (`material.w` 1): limestone whose colour wanders between iron-stained ochre
// and grey in beds and patches, speckled at the grain, with a relief of the same solid
// noise bent into the normal. Solid noise, not a projected texture: steep walls and
// floors are textured alike and no seam shows where projections would meet.
void rock(vec3 p, inout vec3 n, inout vec3 albedo) {
    // A temporal frame's sample stands for its share of the pixel (`Jitter::lod_bias`).
    float footprint = length(fwidth(p)) * exp2(frame.params.z);
    vec4 patches = value_noise(p * vec3(1.1, 2.6, 1.1));
    vec4 grain = value_noise(p * 9.0 + 13.0);
    vec4 fine = value_noise(p * 31.0 + 71.0);
    float g = octave_weight(9.0, footprint);
    float f = octave_weight(31.0, footprint);
    vec3 grey = vec3(0.095, 0.09, 0.085);
    float stain = smoothstep(0.25, 0.8, patches.x);
    albedo = mix(grey, albedo, stain) * (0.91 + g * 0.46 * (grain.x - 0.5))
           * (1.0 + f * 0.36 * (fine.x - 0.5));
    vec3 slope = 0.05 * patches.yzw + g * 0.045 * grain.yzw + f * 0.02 * fine.yzw;
    n = normalize(n - (slope - dot(slope, n) * n));
}

void main() {
    vec3 n = normalize(in_normal);
    vec3 v = normalize(frame.camera_pos.xyz - in_world);
    vec3 l;
    vec3 radiance;
    light_at(frame.sun_dir, frame.sun_color.rgb, in_world, l, radiance);
    vec3 albedo = object.albedo.rgb;
    vec3 geometric = n;
    if (object.material.w > 0.5) {
        rock(in_world, n, albedo);
    }
#ifdef SHADOWED
    radiance *= shadow_visibility(in_world, geometric);
#endif
    vec3 hdr = albedo * hemisphere_ambient(n, frame.sky_color.rgb, frame.ground_color.rgb)
             + sun_light(n, v, l, albedo, radiance, object.material.x, object.material.y)
             + albedo * object.material.z;
    out_color = vec4(tonemap(hdr, frame.params.x), 1.0);
}
