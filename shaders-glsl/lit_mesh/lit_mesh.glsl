// The lit-mesh pass's shading: the body of `lit_mesh.frag` and of
// `lit_mesh_shadowed.frag` (the lamp's light through its shadow map, set 1).
#include "lighting.glsl"
#include "tonemap.glsl"
#include "rock.glsl"
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

// Rock (`material.w` 1): `limestone` over a dark grey (`common/rock.glsl`).
void rock(vec3 p, inout vec3 n, inout vec3 albedo) {
    // A temporal frame's sample stands for its share of the pixel (`Jitter::lod_bias`).
    float footprint = length(fwidth(p)) * exp2(frame.params.z);
    limestone(p, footprint, vec3(0.095, 0.09, 0.085), n, albedo);
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
